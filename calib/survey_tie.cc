// SPDX-License-Identifier: Apache-2.0
#include "calib/survey_tie.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "calib/geodesy.h"

namespace wallcal::calib {
namespace {

// Two control points closer than this cannot fix a rotation (and are almost surely the same
// point entered twice).
constexpr double kCoincidentM = 0.01;
// RTK (2 cm) and a total station (mm) agree to centimetres; a metre means a wrong id, swapped
// coordinates or a wrong datum, not noise.
constexpr double kAbsurdResidualM = 1.0;
constexpr double kMinWallSpanM = 0.5;
// The height span of a wall's survey points from which its lean is fitted (m): at 0.5 m and a
// total station's 3 mm the lean is known to about 0.5°.
constexpr double kMinLeanSpanM = 0.5;
// A fitted lean further from upright than this many of its σ is the wall's (else upright).
constexpr double kLeanSignificance = 4.0;

std::string Metres(double value_m) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << value_m;
  return out.str();
}

Eigen::Matrix2d Rotation(double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

// The one survey point with this id; throws when it is missing or ambiguous.
const io::SurveyPoint& FindControlInSurvey(const std::vector<io::SurveyPoint>& survey,
                                           const std::string& survey_file,
                                           const io::SessionSpec& spec,
                                           const io::ControlPoint& control) {
  const io::SurveyPoint* found = nullptr;
  int count = 0;
  for (const io::SurveyPoint& point : survey) {
    if (point.id != control.id) continue;
    if (found == nullptr) found = &point;
    ++count;
  }
  if (found == nullptr) {
    throw io::InputError(io::Where(spec.file, control.line,
                                   "control point " + control.id + " is not in " + survey_file +
                                       "; expected a survey point with id " + control.id));
  }
  if (count > 1) {
    throw io::InputError(io::Where(spec.file, control.line,
                                   "control point " + control.id + " appears " +
                                       std::to_string(count) + " times in " + survey_file +
                                       "; expected exactly one survey point with that id"));
  }
  return *found;
}

// The rigid 2-D fit of `from` onto `to` leaving out point `skip` (-1: none): the largest
// residual norm of the points used, metres.
double WorstResidualWithout(const std::vector<Eigen::Vector2d>& from,
                            const std::vector<Eigen::Vector2d>& to, int skip) {
  Eigen::Vector2d from_mean = Eigen::Vector2d::Zero(), to_mean = Eigen::Vector2d::Zero();
  int used = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    from_mean += from[i];
    to_mean += to[i];
    ++used;
  }
  from_mean /= used;
  to_mean /= used;
  double sum_dot = 0.0, sum_cross = 0.0;
  for (size_t i = 0; i < from.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    const Eigen::Vector2d a = from[i] - from_mean, b = to[i] - to_mean;
    sum_dot += a.dot(b);
    sum_cross += a.x() * b.y() - a.y() * b.x();
  }
  const Eigen::Matrix2d r = Rotation(std::atan2(sum_cross, sum_dot));
  double worst_m = 0.0;
  for (size_t i = 0; i < from.size(); ++i) {
    if (static_cast<int>(i) == skip) continue;
    worst_m = std::max(worst_m, (r * (from[i] - from_mean) + to_mean - to[i]).norm());
  }
  return worst_m;
}

// What a control point far off the fit means. Two points fit any rotation: only their distance
// apart can disagree, and either may be the wrong one. With three or more, the one whose
// removal leaves the others agreeing is named.
std::string DescribeControlDisagreement(const std::vector<io::ControlPoint>& control,
                                        const std::vector<Eigen::Vector2d>& p_survey,
                                        const std::vector<Eigen::Vector2d>& p_local,
                                        double worst_m) {
  const int n = static_cast<int>(control.size());
  if (n == 2) {
    return "control points " + control[0].id + " and " + control[1].id + " are " +
           Metres((p_survey[0] - p_survey[1]).norm()) + " m apart in the survey but " +
           Metres((p_local[0] - p_local[1]).norm()) +
           " m apart by their lat/lon: one of them has a wrong id or wrong coordinates, and "
           "with two control points the wrong one cannot be told; check both (a digit of lat "
           "or lon?), or add a third control point; expected agreement within " +
           Metres(kAbsurdResidualM) + " m";
  }
  std::vector<int> culprits;
  for (int i = 0; i < n; ++i) {
    if (WorstResidualWithout(p_survey, p_local, i) <= kAbsurdResidualM) culprits.push_back(i);
  }
  if (culprits.size() == 1) {
    const int bad = culprits.front();
    std::string others;
    for (int i = 0; i < n; ++i) {
      if (i != bad) others += (others.empty() ? "" : ", ") + control[i].id;
    }
    return "control point " + control[bad].id + " disagrees with the survey by " +
           Metres(worst_m) + " m or more, while " + others + " agree within " +
           Metres(kAbsurdResidualM) + " m without it: check " + control[bad].id +
           "'s id and lat/lon (a digit?) in session.yaml and its survey coordinates";
  }
  std::string ids;
  for (const io::ControlPoint& c : control) ids += (ids.empty() ? "" : ", ") + c.id;
  return "control points " + ids + " disagree with the survey by up to " + Metres(worst_m) +
         " m and no one of them alone explains it: wrong ids or wrong coordinates in more than "
         "one? expected agreement within " + Metres(kAbsurdResidualM) + " m";
}

// The distinct codes of the survey with their point counts ("CTRL (2), WALL1 (60)"), at most
// 20 of them, for a wall whose code matches none.
std::string CodesFound(const std::vector<io::SurveyPoint>& survey) {
  std::map<std::string, int> counts;
  for (const io::SurveyPoint& point : survey) ++counts[point.code];
  std::string out;
  int shown = 0;
  for (const auto& [code, count] : counts) {
    if (shown++ == 20) {
      out += ", ...";
      break;
    }
    out += (out.empty() ? "" : ", ") + (code.empty() ? std::string("(empty)") : code) + " (" +
           std::to_string(count) + ")";
  }
  return out.empty() ? "none" : out;
}

// The offset (m) from the survey's heights to the GNSS's ellipsoidal heights: the mean of
// (RTK height − surveyed height) over the control points the survey holds; 0 for a rover's
// survey (its heights are ellipsoidal already); NaN when no control point ties them.
double VerticalTie(const std::vector<io::SurveyPoint>& survey, const io::SessionSpec& spec) {
  double sum_m = 0.0;
  int count = 0;
  bool geodetic = !survey.empty();
  for (const io::SurveyPoint& point : survey) geodetic = geodetic && point.frame == io::SurveyFrame::kGeodetic;
  if (geodetic) return 0.0;
  for (const io::ControlPoint& control : spec.control) {
    for (const io::SurveyPoint& point : survey) {
      if (point.id != control.id) continue;
      sum_m += control.h_m - point.z_m;
      ++count;
      break;
    }
  }
  return count > 0 ? sum_m / count : std::numeric_limits<double>::quiet_NaN();
}

// The wall's lean from its points' heights (calib/observation.h, WallGeometry::lean_rad): the
// points' distance across the fitted line against their height, a straight line whose slope
// is tan(lean); fitted when the heights span kMinLeanSpanM. The reference height is the
// points' mean height, tied to the GNSS's by `tie_m` (NaN: untied).
void FitLean(const std::vector<Eigen::Vector2d>& points, const std::vector<double>& heights_m,
             const std::vector<double>& sigmas_m, const Eigen::Vector2d& centroid, double tie_m,
             WallGeometry* wall) {
  const size_t n = points.size();
  double mean_height_m = 0.0;
  for (double h : heights_m) mean_height_m += h / static_cast<double>(n);
  wall->reference_height_m = mean_height_m + tie_m;
  double min_h = heights_m.front(), max_h = heights_m.front();
  for (double h : heights_m) {
    min_h = std::min(min_h, h);
    max_h = std::max(max_h, h);
  }
  if (max_h - min_h < kMinLeanSpanM || n < 3) return;
  // Weighted by 1/σ²: slope = Σ w dh across / Σ w dh², its variance 1 / Σ w dh².
  double sw = 0.0, swh = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = 1.0 / (sigmas_m[i] * sigmas_m[i]);
    sw += w;
    swh += w * heights_m[i];
  }
  const double weighted_mean_h = swh / sw;
  double swhh = 0.0, swha = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = 1.0 / (sigmas_m[i] * sigmas_m[i]);
    const double dh = heights_m[i] - weighted_mean_h;
    swhh += w * dh * dh;
    swha += w * dh * wall->normal_local.dot(points[i] - centroid);
  }
  wall->fitted_lean_rad = std::atan(swha / swhh);
  wall->sigma_lean_rad = 1.0 / std::sqrt(swhh);
  wall->lean_fitted = true;
  // An upright wall's fit scatters about zero by its σ: taken as leaning beyond 4 σ only.
  if (std::abs(wall->fitted_lean_rad) > kLeanSignificance * wall->sigma_lean_rad) {
    wall->lean_rad = wall->fitted_lean_rad;
  }
}

}  // namespace

bool SameSurveyCode(const std::string& a, const std::string& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

SurveyTie TieSurvey(const std::vector<io::SurveyPoint>& survey, const std::string& survey_file,
                    const io::SessionSpec& spec, const LocalFrame& frame,
                    const SurveySigmas& options) {
  const std::vector<io::ControlPoint>& control = spec.control;
  if (control.empty()) {
    throw io::InputError(io::Where(spec.file, 0,
                                   "survey.control is empty; expected at least one control point "
                                   "(a survey point also measured by RTK-GNSS)"));
  }
  const int n = static_cast<int>(control.size());
  std::vector<Eigen::Vector2d> p_survey(n), p_local(n);
  for (int i = 0; i < n; ++i) {
    const io::SurveyPoint& point = FindControlInSurvey(survey, survey_file, spec, control[i]);
    p_survey[i] = Eigen::Vector2d(point.x_m, point.y_m);
    p_local[i] = ToLocal(frame, control[i].lat_deg, control[i].lon_deg);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      const double survey_gap_m = (p_survey[i] - p_survey[j]).norm();
      const double local_gap_m = (p_local[i] - p_local[j]).norm();
      if (survey_gap_m < kCoincidentM || local_gap_m < kCoincidentM) {
        throw io::InputError(
            io::Where(spec.file, control[i].line,
                      "control points " + control[j].id + " and " + control[i].id + " coincide (" +
                          Metres(survey_gap_m) + " m apart in the survey, " + Metres(local_gap_m) +
                          " m by RTK); expected distinct points, ideally at the ends of the site"));
      }
    }
  }

  // Control point error per axis: RTK and total station, independent.
  const double sigma_point_m = std::hypot(options.control_sigma_m, options.total_station_sigma_m);

  SurveyTie tie;
  tie.num_control = n;
  if (n == 1) {
    if (!spec.survey_rotation_rad) {
      throw io::InputError(io::Where(spec.file, control[0].line,
                                     "one control point and no survey.rotation_deg; expected "
                                     "the rotation or a second control point"));
    }
    // Barawid 2007, Eq. 4-5: rotate about the control point, then put it at its RTK position.
    tie.local_R_survey = Rotation(*spec.survey_rotation_rad);
    tie.local_t_survey = p_local[0] - tie.local_R_survey * p_survey[0];
    tie.sigma_rotation_rad = options.rotation_sigma_rad;
    tie.sigma_translation_m = sigma_point_m;
    tie.control_centroid_local = p_local[0];
    tie.control_residuals.push_back({control[0].id, Eigen::Vector2d::Zero()});
    tie.control_rms_m = 0.0;
    return tie;
  }

  // Least-squares rigid fit in 2-D (no scale: both sides are ground metres). With centred
  // coordinates a_i (survey) and b_i (local), the rotation maximising Σ b_i · R a_i has
  // tan θ = Σ (a_i × b_i) / Σ (a_i · b_i).
  Eigen::Vector2d survey_mean = Eigen::Vector2d::Zero(), local_mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < n; ++i) {
    survey_mean += p_survey[i];
    local_mean += p_local[i];
  }
  survey_mean /= n;
  local_mean /= n;
  double sum_dot = 0.0, sum_cross = 0.0, spread2_m2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d a = p_survey[i] - survey_mean;
    const Eigen::Vector2d b = p_local[i] - local_mean;
    sum_dot += a.dot(b);
    sum_cross += a.x() * b.y() - a.y() * b.x();
    spread2_m2 += a.squaredNorm();
  }
  tie.local_R_survey = Rotation(std::atan2(sum_cross, sum_dot));
  tie.local_t_survey = local_mean - tie.local_R_survey * survey_mean;
  tie.control_centroid_local = local_mean;

  double sum_sq_m2 = 0.0;
  int worst = 0;
  double worst_m = -1.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d residual =
        tie.local_R_survey * p_survey[i] + tie.local_t_survey - p_local[i];
    tie.control_residuals.push_back({control[i].id, residual});
    sum_sq_m2 += residual.squaredNorm();
    if (residual.norm() > worst_m) {
      worst_m = residual.norm();
      worst = i;
    }
  }
  tie.control_rms_m = std::sqrt(sum_sq_m2 / n);
  if (worst_m > kAbsurdResidualM) {
    throw io::InputError(io::Where(spec.file, control[worst].line,
                                   DescribeControlDisagreement(control, p_survey, p_local, worst_m)));
  }
  // A point at distance r_i from the centroid, displaced by σ across, turns the fit by σ/r_i;
  // least squares weights by r_i², hence σ_θ² = σ² / Σ r_i².
  tie.sigma_rotation_rad = sigma_point_m / std::sqrt(spread2_m2);
  tie.sigma_translation_m = sigma_point_m / std::sqrt(static_cast<double>(n));
  return tie;
}

std::vector<WallGeometry> FitWalls(const std::vector<io::SurveyPoint>& survey,
                                   const std::string& survey_file, const io::SessionSpec& spec,
                                   const SurveyTie& tie, const SurveySigmas& options) {
  std::vector<WallGeometry> walls;
  for (const io::WallSpec& wall_spec : spec.walls) {
    std::vector<Eigen::Vector2d> points;
    std::vector<double> heights_m;  // the points' heights, in the survey's own vertical datum
    std::vector<double> sigmas_m;  // each point's σ per axis: the file's (a rover's), or the
                                   // total station's
    bool from_rover = true;
    for (const io::SurveyPoint& point : survey) {
      if (!SameSurveyCode(point.code, wall_spec.code)) continue;
      points.push_back(tie.local_R_survey * Eigen::Vector2d(point.x_m, point.y_m) +
                       tie.local_t_survey);
      heights_m.push_back(point.z_m);
      sigmas_m.push_back(point.sigma_m > 0.0 ? point.sigma_m : options.total_station_sigma_m);
      from_rover = from_rover && point.frame == io::SurveyFrame::kGeodetic;
    }
    const int n = static_cast<int>(points.size());
    if (n < 2) {
      const std::string found = n == 0 ? "no survey points" : "only 1 survey point";
      throw io::InputError(io::Where(survey_file, 0,
                                     "wall " + wall_spec.id + ": " + found + " with code " +
                                         wall_spec.code + " (in any case); the survey's codes are " +
                                         CodesFound(survey) + "; expected at least 2"));
    }

    // Total least squares: the line through the centroid along the scatter's major axis.
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& p : points) centroid += p;
    centroid /= n;
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const Eigen::Vector2d& p : points) scatter += (p - centroid) * (p - centroid).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
    Eigen::Vector2d direction = eigen.eigenvectors().col(1);  // eigenvalues ascending
    if (direction.dot(points.back() - points.front()) < 0.0) direction = -direction;
    const Eigen::Vector2d normal(-direction.y(), direction.x());

    double along_min_m = 0.0, along_max_m = 0.0, along_sq_m2 = 0.0, across_sq_m2 = 0.0;
    // Σσ², Σsσ², Σs²σ² over the points (s: along the wall from the centroid), for the fit's σ.
    double var_sum_m2 = 0.0, along_var_sum_m3 = 0.0, along_sq_var_sum_m4 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double along_m = direction.dot(points[i] - centroid);
      const double across_m = normal.dot(points[i] - centroid);
      along_min_m = i == 0 ? along_m : std::min(along_min_m, along_m);
      along_max_m = i == 0 ? along_m : std::max(along_max_m, along_m);
      along_sq_m2 += along_m * along_m;
      across_sq_m2 += across_m * across_m;
      const double var_m2 = sigmas_m[i] * sigmas_m[i];
      var_sum_m2 += var_m2;
      along_var_sum_m3 += along_m * var_m2;
      along_sq_var_sum_m4 += along_m * along_m * var_m2;
    }
    const double span_m = along_max_m - along_min_m;
    if (span_m < kMinWallSpanM) {
      throw io::InputError(io::Where(survey_file, 0,
                                     "wall " + wall_spec.id + ": the survey points with code " +
                                         wall_spec.code + " span only " + Metres(span_m) +
                                         " m; expected at least " + Metres(kMinWallSpanM) +
                                         " m along the wall"));
    }

    WallGeometry wall;
    wall.id = wall_spec.id;
    wall.normal_local = normal;
    wall.offset_m = normal.dot(centroid);
    wall.end_a_local = centroid + along_min_m * direction;
    wall.end_b_local = centroid + along_max_m * direction;
    wall.num_points = n;
    wall.rms_m = std::sqrt(across_sq_m2 / n);

    // Fit (each point off the line by its own σ_i, independent): the offset at the centroid
    // is the points' mean across, Σσ²/n²; the direction Σ s_i e_i / Σs², so Σs²σ²/(Σs²)²; their
    // covariance Σsσ²/(n Σs²) (0 when every σ_i is the same). Moved to the wall's centre
    // (along-coordinate s_c) the offset picks up s_c·δθ.
    const double var_angle_fit = along_sq_var_sum_m4 / (along_sq_m2 * along_sq_m2);
    const double var_centroid_fit = var_sum_m2 / (static_cast<double>(n) * n);
    const double cov_centroid_fit = along_var_sum_m3 / (n * along_sq_m2);
    const double centre_along_m = 0.5 * (along_min_m + along_max_m);
    const double var_offset_fit = var_centroid_fit + 2.0 * centre_along_m * cov_centroid_fit +
                                  centre_along_m * centre_along_m * var_angle_fit;
    // Tie: the whole survey shifts by the translation error and turns about the control
    // centroid; only the along-wall component of the lever moves the wall along its normal.
    const Eigen::Vector2d centre = 0.5 * (wall.end_a_local + wall.end_b_local);
    const double lever_m = direction.dot(centre - tie.control_centroid_local);
    const double var_offset_tie = tie.sigma_translation_m * tie.sigma_translation_m +
                                  std::pow(tie.sigma_rotation_rad * lever_m, 2);
    wall.sigma_offset_m = std::sqrt(var_offset_fit + var_offset_tie);
    wall.sigma_angle_rad =
        std::sqrt(var_angle_fit + tie.sigma_rotation_rad * tie.sigma_rotation_rad);
    wall.cov_offset_angle = cov_centroid_fit + centre_along_m * var_angle_fit +
                            tie.sigma_rotation_rad * tie.sigma_rotation_rad * lever_m;
    wall.from_rover = from_rover;
    wall.tie_sigma_translation_m = tie.sigma_translation_m;
    wall.tie_sigma_rotation_rad = tie.sigma_rotation_rad;
    wall.tie_lever_m = lever_m;
    FitLean(points, heights_m, sigmas_m, centroid, VerticalTie(survey, spec), &wall);
    walls.push_back(wall);
  }
  return walls;
}

}  // namespace wallcal::calib
