// SPDX-License-Identifier: Apache-2.0
// offsets.yaml, the summary and --emit for several scanners (outputs/multi_offsets.h).

#include "outputs/multi_offsets.h"

#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <vector>

#include "common/angles.h"
#include "common/format.h"
#include "io/config/yaml_text.h"
#include "io/version.h"
#include "outputs/json_text.h"
#include "outputs/offsets_document.h"
#include "outputs/summary.h"

namespace wallcal::outputs {
namespace {

using io::YamlNumber;
using io::YamlQuoted;
using io::YamlText;

double Sigma(const Eigen::Matrix3d& covariance, int i) {
  return std::sqrt(std::max(0.0, covariance(i, i)));
}

std::string MountKeys(const std::string& indent, const solvers::Mount& mount,
                      const Eigen::Matrix3d& covariance) {
  std::string out;
  out += indent + "x: " + YamlNumber("%.6f", mount.x_m) + "  # m\n";
  out += indent + "y: " + YamlNumber("%.6f", mount.y_m) + "  # m\n";
  out += indent + "yaw: " + YamlNumber("%.8f", mount.yaw_rad) + "  # rad\n";
  out += indent + "yaw_deg: " + YamlNumber("%.4f", mount.yaw_rad * kRadToDeg) + "\n";
  out += indent + "stddev: {x: " + YamlNumber("%.6f", Sigma(covariance, 0)) +
         ", y: " + YamlNumber("%.6f", Sigma(covariance, 1)) +
         ", yaw_deg: " + YamlNumber("%.4f", Sigma(covariance, 2) * kRadToDeg) + "}\n";
  out += indent + "covariance: [";
  for (int i = 0; i < 9; ++i) {
    out += (i > 0 ? ", " : "") + YamlNumber("%.6e", covariance(i / 3, i % 3));
  }
  out += "]  # 3x3 row-major, order x, y, yaw (m, m, rad)\n";
  return out;
}

// What the σ above is made of: the data's part (the vehicle's errors, the line fits, the
// survey) and the units' range models' (each scanner's range offset and scale, taken as exact
// by the adjustment and carried in its covariance). The two σ add in quadrature.
std::string BudgetKeys(const std::string& indent, const Eigen::Matrix3d& covariance,
                       const Eigen::Matrix3d& units) {
  const Eigen::Matrix3d data = covariance - units;
  const auto line = [](const Eigen::Matrix3d& c) {
    return "{x: " + YamlNumber("%.6f", Sigma(c, 0)) + ", y: " + YamlNumber("%.6f", Sigma(c, 1)) +
           ", yaw_deg: " + YamlNumber("%.4f", Sigma(c, 2) * kRadToDeg) + "}";
  };
  return indent + "sigma_budget:  # m, m, deg; the two add in quadrature to stddev\n" + indent +
         "  data: " + line(data) + "  # vehicle, line fits, survey\n" + indent +
         "  unit_range_models: " + line(units) +
         "  # each unit's range offset and scale (range_model_sigma of its preset)\n";
}

const char* kHeightNote =
    "z = 0: the scanner's height relative to the GNSS antenna is not known (give it as z_m of "
    "the scanner in session.yaml); the 2-D calibration does not measure it";

}  // namespace

std::string FormatSeveralOffsetsYaml(const pipeline::SeveralScannersResult& several,
                                     const EmitFrames& frames) {
  std::string out;
  out += "# The run's verdict: the worst of the scanners' and the relative transforms' below.\n";
  out += "verdict: " + DecisionYaml(several.decision) + "\n";
  out += "# Mounts of the scanners in the vehicle (GNSS antenna) frame: x forward, y left, yaw "
         "ccw.\n";
  out += "scanner_mounts:\n";
  std::vector<std::string> order;
  for (const pipeline::ScannerRun& run : several.scanners) {
    if (!run.joint) continue;
    const pipeline::CalibrationResult& own = run.own;
    const pipeline::JointScannerResult& joint = *run.joint;
    out += "  - id: " + YamlText(run.spec.id) + "\n";
    out += "    parent_frame: " + YamlText(frames.parent) + "\n";
    out += "    child_frame: " + YamlText(run.spec.frame) + "\n";
    out += MountKeys("    ", joint.mount, joint.covariance);
    out += BudgetKeys("    ", joint.covariance, joint.range_model_covariance);
    if (joint.unit_range.estimated) {
      const solvers::JointMountEstimate::UnitRange& u = joint.unit_range;
      out += "    range_model: {offset_m: " + YamlNumber("%.5f", u.offset_m) +
             ", offset_sigma_m: " + YamlNumber("%.5f", u.sigma_offset_m) +
             ", scale: " + YamlNumber("%.6f", u.scale) +
             ", scale_sigma: " + YamlNumber("%.6f", u.sigma_scale) +
             "}  # this unit's ranges off its preset's correction, as estimated\n";
    }
    out += "    time_offset_s: " + YamlNumber("%.4f", joint.time_offset_s) + "\n";
    // Its σ and status as the one-scanner offsets.yaml has them: its own run's (the joint
    // covariance holds the mounts only).
    const pipeline::StreamDelay& offset = own.solve.scanner_offset;
    if (own.solve.estimate.time_offset_estimated) {
      out +=
          "    time_offset_sigma_s: " + YamlNumber("%.4f", offset.sigma_s) + "  # its own run's\n";
      out += "    time_offset_status: \"" + std::string(pipeline::DelayStatusName(offset.status)) +
             "\"\n";
    }
    // The counts and residuals of its own run (the joint adjustment takes its observations).
    const pipeline::Coverage& coverage = own.finish.coverage;
    const solvers::MountEstimate& estimate = own.solve.estimate;
    out += "    quality: {scans_total: " + std::to_string(own.detection.scans_total) +
           ", scans_used: " + std::to_string(coverage.scans_used) +
           ", observations: " + std::to_string(estimate.observations_used) +
           ", outliers: " + std::to_string(estimate.observations_rejected) +
           ", residual_rms_m: " + YamlNumber("%.6f", estimate.residual_rms_m) +
           ", stations: " + std::to_string(own.poses.num_dwells) +
           ", headings_deg: {min: " + YamlNumber("%.4f", coverage.heading_min_deg) +
           ", max: " + YamlNumber("%.4f", coverage.heading_max_deg) + "}}\n";
    out += "    verdict: " + DecisionYaml(joint.decision) + "\n";
    if (joint.change) out += "    change_since_previous: " + ChangeYaml(*joint.change) + "\n";
    for (const char* axis : {".x", ".y", ".yaw"}) order.push_back(run.spec.id + axis);
  }
  out += "# Pose of `to` in the frame of `from` (from = the scanner listed earlier).\n";
  if (several.relative.empty()) {
    out += "relative_mounts: []\n";
  } else {
    out += "relative_mounts:\n";
    for (const pipeline::RelativeMountResult& relative : several.relative) {
      out += "  - from: " + YamlText(relative.from_id) + "\n";
      out += "    to: " + YamlText(relative.to_id) + "\n";
      out += MountKeys("    ", relative.mount.from_T_to, relative.mount.covariance);
      out += BudgetKeys("    ", relative.mount.covariance, relative.range_model_covariance);
      out += "    verdict: " + DecisionYaml(relative.decision) + "\n";
      if (relative.change) {
        out += "    change_since_previous: " + ChangeYaml(*relative.change) + "\n";
      }
    }
  }
  out += "joint_covariance:\n";
  out += "  order: [";
  for (size_t i = 0; i < order.size(); ++i) out += (i > 0 ? ", " : "") + YamlQuoted(order[i]);
  out += "]  # m, m, rad per scanner\n";
  out += "  matrix:\n";
  const Eigen::MatrixXd& c = several.joint.covariance;
  for (int r = 0; r < c.rows(); ++r) {
    out += "    - [";
    for (int col = 0; col < c.cols(); ++col) {
      out += (col > 0 ? ", " : "") + YamlNumber("%.6e", c(r, col));
    }
    out += "]\n";
  }
  std::string refused;
  for (const pipeline::ScannerRun& run : several.scanners) {
    if (run.joint) continue;
    refused +=
        "  - {id: " + YamlText(run.spec.id) + ", reason: " + YamlQuoted(run.own.Why()) + "}\n";
  }
  out += refused.empty() ? "refused: []\n" : "refused:\n" + refused;
  if (!several.previous_input.role.empty()) {
    const auto list = [](const std::vector<std::string>& ids) {
      std::string text = "[";
      for (size_t i = 0; i < ids.size(); ++i) text += (i ? ", " : "") + YamlText(ids[i]);
      return text + "]";
    };
    out += "# --compare: the scanners found in one of the two files only.\n";
    out += "compared_with: {previous: " + YamlQuoted(several.previous_input.path) +
           ", not_in_previous: " + list(several.not_in_previous) +
           ", only_in_previous: " + list(several.only_in_previous) + "}\n";
  }
  out += "method: ceres\n";
  out += "source:\n";
  out += "  session: " + YamlQuoted(several.session.file) + "\n";
  out += "  tool_version: " + YamlQuoted(io::kToolVersion) + "\n";
  const pipeline::Provenance& first = several.scanners.front().own.decided.provenance;
  if (!first.created_utc.empty()) out += "  created_utc: " + YamlQuoted(first.created_utc) + "\n";
  if (!first.command_line.empty()) {
    out += "  command_line: [";
    for (size_t i = 0; i < first.command_line.size(); ++i) {
      out += (i ? ", " : "") + YamlQuoted(first.command_line[i]);
    }
    out += "]\n";
  }
  std::set<std::string> seen;
  std::string inputs;
  for (const pipeline::ScannerRun& run : several.scanners) {
    for (const io::InputFileDigest& input : run.own.decided.provenance.inputs) {
      if (!seen.insert(input.role + "\n" + input.path).second) continue;
      inputs += "    - {role: " + YamlQuoted(input.role) + ", path: " + YamlQuoted(input.path) +
                ", sha256: " + (input.sha256.empty() ? std::string("null") : input.sha256) +
                "}\n";
    }
  }
  const io::InputFileDigest& previous = several.previous_input;
  if (!previous.role.empty() && seen.insert(previous.role + "\n" + previous.path).second) {
    inputs += "    - {role: " + YamlQuoted(previous.role) + ", path: " +
              YamlQuoted(previous.path) + ", sha256: " +
              (previous.sha256.empty() ? std::string("null") : previous.sha256) + "}\n";
  }
  if (!inputs.empty()) out += "  inputs:\n" + inputs;
  return out;
}

namespace {

// ", clock offset V ± σ s, STATUS": the value `offset_s` (the joint adjustment's, or its own
// run's), the σ and status of the scanner's own run (as its page shows them); the value alone
// when its run did not estimate it.
std::string ClockText(const pipeline::CalibrationResult& own, double offset_s) {
  const pipeline::StreamDelay& offset = own.solve.scanner_offset;
  if (!own.solve.estimate.time_offset_estimated) return Format(", clock offset %.4f s", offset_s);
  return Format(", clock offset %.4f ± %.4f s, %s", offset_s, offset.sigma_s,
                pipeline::DelayStatusName(offset.status));
}

}  // namespace

std::string FormatSeveralSummary(const pipeline::SeveralScannersResult& several) {
  std::string out = "calibrate: " + several.session.name + ": " +
                    std::to_string(several.scanners.size()) + " scanners\n";
  const auto reasons = [&out](const pipeline::Decision& decision) {
    for (const std::string& reason : decision.reasons) out += "      - " + reason + "\n";
  };
  if (several.outcome != pipeline::SeveralOutcome::kFailed) {
    out += std::string("  verdict    ") + pipeline::VerdictName(several.decision.verdict) +
           " (the worst of the scanners and relative transforms below)\n";
    out += "  mounts     the joint adjustment of the scanners calibrated\n";
  } else {
    out += "  mounts     each scanner's own run (no joint adjustment: nothing is written)\n";
  }
  for (const pipeline::ScannerRun& run : several.scanners) {
    const pipeline::CalibrationResult& own = run.own;
    if (run.refused()) {
      out += "  " + run.spec.id + ": REFUSED: " + own.Why() + "\n";
      continue;
    }
    // The joint result; its own run's when the joint adjustment failed.
    const solvers::Mount& m = run.joint ? run.joint->mount : own.solve.estimate.mount;
    const Eigen::Matrix3d& c = run.joint ? run.joint->covariance : own.solve.estimate.covariance;
    const pipeline::Decision& decision = run.joint ? run.joint->decision : own.decided.decision;
    const std::optional<pipeline::Change>& change =
        run.joint ? run.joint->change : own.decided.change;
    const double offset_s = run.joint ? run.joint->time_offset_s : own.solve.scanner_offset.value_s;
    out += "  " + run.spec.id + " (" + pipeline::VerdictName(decision.verdict) + "): " +
           Format("x %.4f ± %.4f m, y %.4f ± %.4f m, yaw %.3f ± %.3f deg", m.x_m, Sigma(c, 0),
                  m.y_m, Sigma(c, 1), m.yaw_rad * kRadToDeg, Sigma(c, 2) * kRadToDeg) +
           ClockText(own, offset_s) +
           Format(", %d observations, %lld scans used", own.solve.estimate.observations_used,
                  static_cast<long long>(own.finish.coverage.scans_used)) +
           "\n";
    if (run.joint && run.joint->unit_range.estimated) {
      const solvers::JointMountEstimate::UnitRange& u = run.joint->unit_range;
      out += Format("    its ranges: offset %+.1f ± %.1f mm, scale %+.5f ± %.5f off its preset's "
                    "correction\n",
                    u.offset_m * 1e3, u.sigma_offset_m * 1e3, u.scale, u.sigma_scale);
    }
    reasons(decision);
    if (change) out += "    change " + ChangeText(*change) + "\n";
  }
  for (const pipeline::RelativeMountResult& relative : several.relative) {
    const solvers::Mount& m = relative.mount.from_T_to;
    const Eigen::Matrix3d& c = relative.mount.covariance;
    out += "  " + relative.to_id + " in " + relative.from_id + " (" +
           pipeline::VerdictName(relative.decision.verdict) + "): " +
           Format("x %.4f ± %.4f m, y %.4f ± %.4f m, yaw %.3f ± %.3f deg", m.x_m, Sigma(c, 0),
                  m.y_m, Sigma(c, 1), m.yaw_rad * kRadToDeg, Sigma(c, 2) * kRadToDeg) +
           "\n";
    const Eigen::Matrix3d& u = relative.range_model_covariance;
    if (u.trace() > 0.0) {
      out += Format("    of which the units' range offsets and scales: ± %.4f m, ± %.4f m, ± %.3f "
                    "deg (the data alone: ± %.4f m, ± %.4f m, ± %.3f deg)\n",
                    Sigma(u, 0), Sigma(u, 1), Sigma(u, 2) * kRadToDeg, Sigma(c - u, 0),
                    Sigma(c - u, 1), Sigma(c - u, 2) * kRadToDeg);
    }
    reasons(relative.decision);
    if (relative.change) out += "    change " + ChangeText(*relative.change) + "\n";
  }
  for (const std::string& id : several.not_in_previous) {
    out += "  scanner '" + id + "' is not in " + several.previous_input.path +
           ": nothing to compare it with\n";
  }
  for (const std::string& id : several.only_in_previous) {
    out += "  scanner '" + id + "' of " + several.previous_input.path +
           " is not calibrated in this run\n";
  }
  if (!several.message.empty()) out += "  " + several.message + "\n";
  out += Format("  time       %.1f s\n", several.seconds);
  return out;
}

std::string FormatSeveralEmit(EmitFormat format, const pipeline::SeveralScannersResult& several,
                              const EmitFrames& frames) {
  std::vector<const pipeline::ScannerRun*> runs;
  for (const pipeline::ScannerRun& run : several.scanners) {
    if (!run.joint) continue;
    if (!IsValidFrameName(run.spec.frame) || run.spec.frame == frames.parent ||
        run.spec.frame == frames.base) {
      throw std::invalid_argument("scanner '" + run.spec.id + "': frame '" + run.spec.frame +
                                  "' is not a tf2 frame name of its own");
    }
    runs.push_back(&run);
  }
  std::vector<PlanarTransform> joints;
  const std::optional<io::AntennaInBase>& antenna = several.session.antenna_in_base;
  if (antenna) joints.push_back(BaseToAntenna(*antenna, frames));
  for (const pipeline::ScannerRun* run : runs) {
    EmitFrames own = frames;
    own.child = run->spec.frame;
    joints.push_back(AntennaToLaser(run->joint->mount, own, run->spec.z_m.value_or(0.0)));
    joints.back().pitch_rad = run->spec.tilt.pitch_rad;
    joints.back().roll_rad = run->spec.tilt.roll_rad;
  }
  std::string out;
  switch (format) {
    case EmitFormat::kRos2StaticTf:
      for (size_t i = 0; i < joints.size(); ++i) {
        const bool scanner = !antenna || i > 0;
        if (scanner && !runs[antenna ? i - 1 : i]->spec.z_m) {
          out += "# " + joints[i].parent + " -> " + joints[i].child + ": " + kHeightNote + "\n";
        }
        out += Ros2StaticTfLine(joints[i]);
      }
      break;
    case EmitFormat::kUrdf: {
      // The z = 0 note once for each scanner without z_m, naming its joint as the ROS 2 lines
      // do, inside the document (after its prologue, before <robot>).
      std::string notes;
      for (size_t i = 0; i < runs.size(); ++i) {
        if (runs[i]->spec.z_m) continue;
        const PlanarTransform& t = joints[antenna ? i + 1 : i];
        notes += "<!-- " + t.parent + " -> " + t.child + ": " + kHeightNote + " -->\n";
      }
      std::string tree = UrdfTree(joints, true);
      tree.insert(tree.find("<robot "), notes);
      out += tree;
      break;
    }
    case EmitFormat::kJson: {
      out += "{\n  \"method\": \"ceres\",\n  \"parent_frame\": \"" + frames.parent + "\",\n";
      out += "  \"scanners\": [";
      for (size_t i = 0; i < runs.size(); ++i) {
        const pipeline::ScannerRun& run = *runs[i];
        const PlanarTransform& t = joints[antenna ? i + 1 : i];
        const Eigen::Matrix3d& c = run.joint->covariance;
        out += std::string(i ? ",\n" : "\n") + "    {\"id\": " + JsonString(run.spec.id) +
               ", \"child_frame\": " + JsonString(t.child) +
               ", \"mount\": {\"x_m\": " + JsonNum(t.x_m) +
               ", \"y_m\": " + JsonNum(t.y_m) + ", \"z_m\": " + JsonNum(t.z_m) + ", \"yaw_rad\": " +
               JsonNum(t.yaw_rad) + ", \"yaw_deg\": " + JsonNum(t.yaw_rad * kRadToDeg) +
               "}, \"z_known\": " + (run.spec.z_m ? "true" : "false") + ", \"sigma\": {\"x_m\": " +
               JsonNum(Sigma(c, 0)) + ", \"y_m\": " + JsonNum(Sigma(c, 1)) + ", \"yaw_rad\": " +
               JsonNum(Sigma(c, 2)) + ", \"yaw_deg\": " + JsonNum(Sigma(c, 2) * kRadToDeg) +
               "}, \"covariance\": {\"order\": [\"x_m\", \"y_m\", \"yaw_rad\"], \"matrix\": [";
        for (int r = 0; r < 3; ++r) {
          out += r ? ", [" : "[";
          for (int col = 0; col < 3; ++col) out += (col ? ", " : "") + JsonNum(c(r, col));
          out += "]";
        }
        out += "]}, \"verdict\": " + JsonDecision(run.joint->decision) + "}";
      }
      out += "\n  ],\n  \"relative\": [";
      for (size_t i = 0; i < several.relative.size(); ++i) {
        const pipeline::RelativeMountResult& relative = several.relative[i];
        const solvers::Mount& m = relative.mount.from_T_to;
        const Eigen::Matrix3d& c = relative.mount.covariance;
        out += std::string(i ? ",\n" : "\n") + "    {\"from\": " + JsonString(relative.from_id) +
               ", \"to\": " + JsonString(relative.to_id) + ", \"x_m\": " + JsonNum(m.x_m) +
               ", \"y_m\": " + JsonNum(m.y_m) + ", \"yaw_rad\": " + JsonNum(m.yaw_rad) +
               ", \"yaw_deg\": " + JsonNum(m.yaw_rad * kRadToDeg) + ", \"sigma\": {\"x_m\": " +
               JsonNum(Sigma(c, 0)) + ", \"y_m\": " + JsonNum(Sigma(c, 1)) + ", \"yaw_rad\": " +
               JsonNum(Sigma(c, 2)) + ", \"yaw_deg\": " + JsonNum(Sigma(c, 2) * kRadToDeg) +
               "}, \"verdict\": " + JsonDecision(relative.decision) + "}";
      }
      out += "\n  ],\n";
      out += "  \"verdict\": " + JsonDecision(several.decision) + ",\n";
      out += JsonBaseLinkMember(antenna ? &joints.front() : nullptr);
      out += "}\n";
      break;
    }
  }
  return out;
}

}  // namespace wallcal::outputs
