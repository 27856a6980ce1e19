// SPDX-License-Identifier: Apache-2.0
#pragma once
// One scan's wall observation with its scanner unit's range model as a parameter block of the
// joint adjustment (solvers/joint_mounts.cc): u = [δb_m, δk], the unit's range offset (m) and
// relative scale error off the preset's correction. Its ranges then read δb + δk·r too, which
// moves the scan's line fit by
//   rho:   G_ρ = drho_db·δb + rho·δk      (m; drho_db from calib::WallObservation, rho the
//                                          scan's reference, solvers/unit_scale_reference.h)
//   theta: G_θ = dtheta_db·δb             (rad; a scale error does not turn the line)
// so the measured line is the true one plus (G_ρ, G_θ). Wraps the cost of that one scan
// (a WallSliceCost of one scan, or an EpochNoiseCost around one) and evaluates it with its
// prediction moved by that much, through the two blocks the prediction meets linearly and alone
// (wall_line_cost.h): the wall's shift δd (rho_pred gains sign·δd, and nothing else does) and
// the mount's yaw (theta_pred loses yaw, and rho_pred does not depend on it):
//   δd' = δd + sign·G_ρ,   yaw' = yaw − G_θ.
// The residuals, their loss and units are the wrapped cost's; the Jacobian of u follows from
// the wrapped cost's Jacobians of δd and yaw by the chain rule.
//
// Parameter blocks: the wrapped cost's (mount 3 and wall 2 first), then u (2).

#include <ceres/cost_function.h>

#include <memory>

namespace wallcal::solvers {

class UnitRangeCost : public ceres::CostFunction {
 public:
  // sign: the observation's side of the wall (WallLineMeasurement::sign, ±1); drho_db (m/m),
  // dtheta_db (rad/m): the line fit's range-offset gain; rho_m: the rho the scale error
  // multiplies (UnitScaleReferences: not the scan's measured one).
  UnitRangeCost(std::unique_ptr<ceres::CostFunction> scan, double sign, double drho_db,
                double dtheta_db, double rho_m);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::unique_ptr<ceres::CostFunction> scan_;
  double sign_, drho_db_, dtheta_db_, rho_m_;
};

}  // namespace wallcal::solvers
