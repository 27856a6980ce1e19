// SPDX-License-Identifier: Apache-2.0
// calibrate --report: the page is well-formed (XML-strict), self-contained, and has its sections
// and plots, for a real calibration of a simulated session.

#include "common/angles.h"
#include "outputs/report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/config/session_reader.h"
#include "outputs/multi_report.h"
#include "pipeline/calibration.h"
#include "pipeline/multi_scanner.h"
#include "sim/simulated_session.h"
#include "test/support/expect_text.h"
#include "test/support/flow_names.h"
#include "test/support/scratch_files.h"
#include "test/support/shipped_presets.h"
#include "test/support/simulated_sessions.h"

namespace wallcal {


namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchDir;
using testing_support::ShippedScenarioPath;

// ---- A strict XML well-formedness checker ----
// Elements must nest and close in order; attribute values quoted; '&' only in the five named
// entities or numeric references; '<' only opening markup; one root element. <!DOCTYPE ...> and
// <!-- comments --> are allowed. Returns "" when well-formed, else what is wrong and where.
std::string XmlProblem(const std::string& s) {
  std::vector<std::string> stack;
  int roots = 0;
  size_t i = 0;
  auto where = [&](size_t at) {
    return " at offset " + std::to_string(at) + ": '" + s.substr(at, 60) + "'";
  };
  auto entity_ok = [&](size_t at, size_t* next) {
    const size_t semi = s.find(';', at);
    if (semi == std::string::npos || semi - at > 10) return false;
    const std::string name = s.substr(at + 1, semi - at - 1);
    static const std::regex kEntity("^(amp|lt|gt|quot|apos|#[0-9]+|#x[0-9a-fA-F]+)$");
    if (!std::regex_match(name, kEntity)) return false;
    *next = semi + 1;
    return true;
  };
  auto is_name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' || c == '.';
  };
  while (i < s.size()) {
    const char c = s[i];
    if (c == '&') {
      size_t next = 0;
      if (!entity_ok(i, &next)) return "stray '&'" + where(i);
      i = next;
      continue;
    }
    if (c != '<') {
      if (stack.empty() && !std::isspace(static_cast<unsigned char>(c))) {
        return "text outside the root element" + where(i);
      }
      ++i;
      continue;
    }
    if (s.compare(i, 4, "<!--") == 0) {
      const size_t end = s.find("-->", i + 4);
      if (end == std::string::npos) return "unclosed comment" + where(i);
      i = end + 3;
      continue;
    }
    if (s.compare(i, 9, "<!DOCTYPE") == 0) {
      if (roots > 0 || !stack.empty()) return "DOCTYPE after the root" + where(i);
      const size_t end = s.find('>', i);
      if (end == std::string::npos) return "unclosed DOCTYPE" + where(i);
      i = end + 1;
      continue;
    }
    size_t p = i + 1;
    const bool closing = p < s.size() && s[p] == '/';
    if (closing) ++p;
    std::string name;
    while (p < s.size() && is_name_char(s[p])) name += s[p++];
    if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) {
      return "stray '<'" + where(i);
    }
    if (closing) {
      while (p < s.size() && std::isspace(static_cast<unsigned char>(s[p]))) ++p;
      if (p >= s.size() || s[p] != '>') return "malformed end tag" + where(i);
      if (stack.empty() || stack.back() != name) {
        return "</" + name + "> closes " + (stack.empty() ? std::string("nothing") : "<" + stack.back() + ">") + where(i);
      }
      stack.pop_back();
      i = p + 1;
      continue;
    }
    // Attributes.
    std::vector<std::string> seen;
    bool self_closing = false;
    while (true) {
      const size_t before = p;
      while (p < s.size() && std::isspace(static_cast<unsigned char>(s[p]))) ++p;
      if (p >= s.size()) return "unclosed tag" + where(i);
      if (s[p] == '>') { ++p; break; }
      if (s[p] == '/') {
        if (p + 1 < s.size() && s[p + 1] == '>') { self_closing = true; p += 2; break; }
        return "stray '/' in tag" + where(i);
      }
      if (p == before) return "attributes not separated by space" + where(i);
      std::string attribute;
      while (p < s.size() && is_name_char(s[p])) attribute += s[p++];
      if (attribute.empty()) return "bad attribute name" + where(p);
      for (const std::string& a : seen) {
        if (a == attribute) return "duplicate attribute " + attribute + where(i);
      }
      seen.push_back(attribute);
      if (p >= s.size() || s[p] != '=') return "attribute without a value: " + attribute + where(i);
      ++p;
      if (p >= s.size() || (s[p] != '"' && s[p] != '\'')) return "unquoted attribute " + attribute + where(i);
      const char quote = s[p++];
      while (p < s.size() && s[p] != quote) {
        if (s[p] == '<') return "'<' in attribute value" + where(p);
        if (s[p] == '&') {
          size_t next = 0;
          if (!entity_ok(p, &next)) return "stray '&' in attribute" + where(p);
          p = next;
          continue;
        }
        ++p;
      }
      if (p >= s.size()) return "unterminated attribute value" + where(i);
      ++p;
    }
    if (stack.empty()) {
      if (++roots > 1) return "second root element" + where(i);
    }
    if (!self_closing) stack.push_back(name);
    i = p;
  }
  if (!stack.empty()) return "<" + stack.back() + "> never closed";
  if (roots != 1) return "no root element";
  return "";
}

// "" when the page fetches nothing and runs nothing, else the offending text.
std::string SelfContainedProblem(const std::string& html) {
  std::string lower = html;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* banned : {"<script", "<link", "<iframe", "<object", "<embed", "@import",
                             "@font-face", "javascript:"}) {
    if (lower.find(banned) != std::string::npos) return std::string("contains ") + banned;
  }
  // Event handler attributes (onload=, onclick=, ...).
  static const std::regex kHandler("<[^>]*\\son[a-z]+\\s*=");
  if (std::regex_search(lower, kHandler)) return "event handler attribute";
  // Every http(s) URL must be the SVG namespace.
  for (size_t at = lower.find("http"); at != std::string::npos; at = lower.find("http", at + 4)) {
    const std::string rest = lower.substr(at, 30);
    if (rest.rfind("http://", 0) != 0 && rest.rfind("https://", 0) != 0) continue;
    if (rest.rfind("http://www.w3.org/2000/svg\"", 0) != 0) return "URL " + html.substr(at, 60);
    if (at < 7 || lower.compare(at - 7, 7, "xmlns=\"") != 0) return "SVG namespace outside xmlns";
  }
  if (lower.find("//") != std::string::npos) {
    // Protocol-relative URLs ("//host/...") in attributes.
    static const std::regex kRelative("(src|href)\\s*=\\s*[\"']//");
    if (std::regex_search(lower, kRelative)) return "protocol-relative URL";
  }
  // src/href/url(...) only to data: URIs or fragments of this page.
  static const std::regex kRef("(src|href|xlink:href)\\s*=\\s*[\"']([^\"']*)[\"']");
  for (auto it = std::sregex_iterator(lower.begin(), lower.end(), kRef); it != std::sregex_iterator(); ++it) {
    const std::string target = (*it)[2];
    if (target.rfind("#", 0) != 0 && target.rfind("data:", 0) != 0) return "reference to " + target;
  }
  static const std::regex kUrl("url\\(\\s*['\"]?([^)'\"]*)");
  for (auto it = std::sregex_iterator(lower.begin(), lower.end(), kUrl); it != std::sregex_iterator(); ++it) {
    const std::string target = (*it)[1];
    if (target.rfind("#", 0) != 0 && target.rfind("data:", 0) != 0) return "url() to " + target;
  }
  return "";
}

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// One calibrated simulated session shared by the tests (calibrating takes a fraction of a second,
// but there is no reason to repeat it).
class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir = FreshScratchDir("session");
    WriteSimulatedSession(sim::ReadSimulationConfig(ShippedScenarioPath("lms291_sapporo")), 7, dir.string());
    CalibrateRequest request;
    request.session_path = dir.string();
    request.collect_report_data = true;
    result_ = std::make_unique<CalibrationResult>(RunCalibration(request));
    html_ = std::make_unique<std::string>(FormatReportHtml(*result_));
  }
  static void TearDownTestSuite() {
    result_.reset();
    html_.reset();
  }
  static std::unique_ptr<CalibrationResult> result_;
  static std::unique_ptr<std::string> html_;
};
std::unique_ptr<CalibrationResult> ReportTest::result_;
std::unique_ptr<std::string> ReportTest::html_;

TEST(XmlCheckerTest, RejectsBrokenMarkup) {
  // The checks below rely on the checker: it must say no to each kind of error. Each piece of
  // markup, and whether it is well-formed:
  const std::pair<const char*, bool> kMarkup[] = {
      {"<a><b></b></a>", true},
      {"<!DOCTYPE html>\n<a x=\"1\" y='2'>t &amp; &#176; &#x3b1;<b/></a>\n", true},
      {"<a><b></a></b>", false},
      {"<a><b></b>", false},
      {"<a x=1></a>", false},
      {"<a x></a>", false},
      {"<a>fish & chips</a>", false},
      {"<a>1 < 2</a>", false},
      {"<a x=\"a<b\"></a>", false},
      {"<a></a><b></b>", false},
      {"<a x=\"1\"x=\"2\"></a>", false},
      {"<a>&nbsp;</a>", false},
      {"<meta charset=\"utf-8\"><a></a>", false},
  };
  for (const auto& [text, accepted] : kMarkup) {
    EXPECT_EQ(XmlProblem(text).empty(), accepted) << text << ": " << XmlProblem(text);
  }
}

TEST(XmlCheckerTest, SelfContainedCheckCatchesFetchesAndScripts) {
  // Each page, and whether it fetches and runs nothing.
  const std::pair<const char*, bool> kPages[] = {
      {"<svg xmlns=\"http://www.w3.org/2000/svg\"><a href=\"#x\"/></svg>", true},
      {"<script>1</script>", false},
      {"<link rel=\"stylesheet\" href=\"a.css\"/>", false},
      {"<img src=\"plot.png\"/>", false},
      {"<img src=\"https://x.org/a.png\"/>", false},
      {"<style>@import 'x.css';</style>", false},
      {"<div style=\"background:url(a.png)\"></div>", false},
      {"<p>see http://example.com</p>", false},
      {"<body onload=\"x()\"></body>", false},
      {"<img src=\"data:image/png;base64,AAAA\"/>", true},
  };
  for (const auto& [text, accepted] : kPages) {
    EXPECT_EQ(SelfContainedProblem(text).empty(), accepted)
        << text << ": " << SelfContainedProblem(text);
  }
}

TEST_F(ReportTest, CalibrationOfTheSimulatedSessionSucceeded) {
  ASSERT_TRUE(result_->solve.estimate.usable) << result_->solve.estimate.message;
}

TEST_F(ReportTest, PageIsWellFormed) { EXPECT_EQ(XmlProblem(*html_), ""); }

TEST_F(ReportTest, PageIsSelfContained) { EXPECT_EQ(SelfContainedProblem(*html_), ""); }

TEST_F(ReportTest, PageHasEverySection) {
  for (const char* id : {"mount", "warnings", "site-map", "scans", "hough", "residuals", "coverage",
                         "counts"}) {
    EXPECT_EQ(Count(*html_, std::string("id=\"") + id + "\""), 1) << id;
  }
}

TEST_F(ReportTest, PageHasThePlots) {
  // Ellipse, site map, 4 scans, Hough, 4 residual panels, coverage.
  EXPECT_GE(Count(*html_, "<svg "), 12);
  EXPECT_EQ(Count(*html_, "<svg "), Count(*html_, "</svg>"));
  // Every plot's clip path id is unique (a repeated id would clip one plot by another's box).
  std::regex clip("clipPath id=\"([a-z0-9]+)\"");
  std::vector<std::string> ids;
  for (auto it = std::sregex_iterator(html_->begin(), html_->end(), clip); it != std::sregex_iterator(); ++it) {
    const std::string id = (*it)[1];
    EXPECT_EQ(std::count(ids.begin(), ids.end(), id), 0) << id;
    ids.push_back(id);
  }
  // Axes carry units.
  for (const char* label : {"x, grid east (m)", "residual (mm)", "x, scanner forward (m)",
                            "range of the characteristic beam (m)", "incidence angle on the wall (deg)",
                            "(deg)"}) {
    EXPECT_NE(html_->find(label), std::string::npos) << label;
  }
}

TEST_F(ReportTest, PageShowsTheMountWithSigmaAndTheCounts) {
  char x[32], sx[32];
  std::snprintf(x, sizeof(x), "%.4f", result_->solve.estimate.mount.x_m);
  std::snprintf(sx, sizeof(sx), "%.4f", std::sqrt(result_->solve.estimate.covariance(0, 0)));
  EXPECT_NE(html_->find(x), std::string::npos) << x;
  EXPECT_NE(html_->find(sx), std::string::npos) << sx;
  EXPECT_NE(html_->find(">" + std::to_string(result_->detection.scans_total) + "<"),
            std::string::npos);
  EXPECT_NE(html_->find(">" + std::to_string(result_->finish.coverage.scans_used) + "<"),
            std::string::npos);
  EXPECT_NE(html_->find("RTK fixed"), std::string::npos);
  // The scan panels found the wall again in every scan shown.
  EXPECT_EQ(html_->find("Not detected again"), std::string::npos);
  // Simulated sessions carry their truth: the ellipse plot marks it.
  EXPECT_NE(html_->find("truth"), std::string::npos);
}

TEST_F(ReportTest, ResidualAnalysisRepeatabilityAndForceAreShownWhenPresent) {
  CalibrationResult r = *result_;
  r.loaded.session.name = "a<b & \"c\"";  // must be escaped
  r.solve.forced = true;
  r.finish.residual_analysis.done = true;
  r.finish.residual_analysis.robust_sigma_m = 0.0031;
  ResidualTrend trend;
  trend.against = analysis::TrendAxis::kRange;
  trend.unit = "m/m";
  trend.slope = 0.002;
  trend.significance = 5.5;
  trend.flagged = true;
  trend.message = "range scale error: check k";
  r.finish.residual_analysis.trends.push_back(trend);
  r.finish.residual_analysis.flags.push_back("residuals grow with range <k>");
  r.finish.repeatability.done = true;
  RepeatabilitySplit split;
  split.name = "first half";
  split.usable = true;
  split.mount = r.solve.estimate.mount;
  split.mount.x_m += 0.01;
  r.finish.repeatability.splits.push_back(split);
  r.solve.scanner_offset.value_s = 0.0123;
  r.solve.scanner_offset.sigma_s = 0.0011;
  const std::string html = FormatReportHtml(r);
  EXPECT_EQ(XmlProblem(html), "");
  testing_support::ExpectContains(html, {
      "TREND FLAGGED",
      "range scale error: check k",
      "residuals grow with range &lt;k&gt;",
      "Repeatability",
      "first half",
      "--force",
      "0.0123",
      "a&lt;b &amp; &quot;c&quot;"
  });
}

TEST_F(ReportTest, WriteReportCreatesTheFolderAndTheFile) {
  const fs::path dir = FreshScratchDir("write") / "nested" / "out";
  const std::string path = WriteReport(*result_, dir.string());
  EXPECT_EQ(fs::path(path), dir / "report.html");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), *html_);
}

TEST(ReportUnusableTest, ARefusedEstimateStillGivesAWellFormedReport) {
  const fs::path dir = testing_support::NarrowHeadingsSession("narrow");
  CalibrateRequest request;
  request.session_path = dir.string();
  request.collect_report_data = true;
  const CalibrationResult result = RunCalibration(request);
  ASSERT_FALSE(result.solve.estimate.usable);
  const std::string html = FormatReportHtml(result);
  EXPECT_EQ(XmlProblem(html), "");
  EXPECT_EQ(SelfContainedProblem(html), "");
  testing_support::ExpectContains(html, {"NOT DETERMINED", "id=\"counts\""});
}

// ---- The page of several scanners (outputs/multi_report.h) ----------------------------------

TEST(SeveralReportTest, IndexShowsEachScannerTheRelativeTransformAndOneSiteMap) {
  const fs::path dir = FreshScratchDir("two_scanners");
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/two_corner_scanners.yaml");
  config.num_stations = 6;
  config.dwell_s = 3.0;
  WriteSimulatedSession(config, 7, dir.string());
  CalibrateRequest request;
  request.session_path = dir.string();
  request.collect_report_data = true;
  const pipeline::SeveralScannersResult several = pipeline::RunSeveralScanners(request, false);
  ASSERT_EQ(several.outcome, pipeline::SeveralOutcome::kAll) << several.message;
  const std::string html = outputs::FormatSeveralReportHtml(several);
  EXPECT_EQ(XmlProblem(html), "");
  // The links to the scanners' own pages beside it (ID/report.html) are the only references out
  // of the page; a link is followed by the reader, never fetched.
  std::string own_links_removed = html;
  for (const pipeline::ScannerRun& run : several.scanners) {
    const std::string link = "href=\"" + run.spec.id + "/report.html\"";
    for (size_t at = own_links_removed.find(link); at != std::string::npos;
         at = own_links_removed.find(link, at)) {
      own_links_removed.replace(at, link.size(), "href=\"#scanners\"");
    }
  }
  EXPECT_EQ(SelfContainedProblem(own_links_removed), "");
  for (const char* id : {"decision", "scanners", "relative", "site-map"}) {
    EXPECT_EQ(Count(html, std::string("id=\"") + id + "\""), 1) << id;
  }
  // One site map holds both scanners' detections and their positions at the stations.
  EXPECT_EQ(Count(html, "<svg "), 1);
  for (const pipeline::ScannerRun& run : several.scanners) {
    const size_t drawn = std::min<size_t>(run.own.solve.observations.size(), 1500);
    EXPECT_NE(html.find(run.spec.id + ": detected wall lines (" + std::to_string(drawn) + " drawn)"),
              std::string::npos)
        << run.spec.id;
    EXPECT_NE(html.find("<a href=\"" + run.spec.id + "/report.html\">"), std::string::npos);
  }
  testing_support::ExpectContains(
      html, {"front_right in front_left", ">ACCEPT<", "acceptance.relative_*", "x, grid east (m)"});
  // Each drawn detection lies on the surveyed wall it was matched to: within 0.1 m of its line
  // (the mount's σ, 13 mm and 0.05° (13 mm at 15 m), and the RTK error, 15 mm, give a few cm
  // at 4.5 σ; a wrong side or frame puts it metres off) and within its ends.
  for (const pipeline::ScannerRun& run : several.scanners) {
    ASSERT_TRUE(run.joint) << run.spec.id;
    for (const calib::WallObservation& o : run.own.solve.observations) {
      const calib::WallGeometry& wall = run.own.survey.walls.at(o.wall_index);
      const auto [a, b] = outputs::DetectionSegmentLocal(o, wall, run.joint->mount);
      const Eigen::Vector2d along = (wall.end_b_local - wall.end_a_local).normalized();
      const Eigen::Vector2d normal(-along.y(), along.x());
      for (const Eigen::Vector2d& p : {a, b}) {
        ASSERT_LT(std::abs(normal.dot(p - wall.end_a_local)), 0.1) << run.spec.id;
        const double s_m = along.dot(p - wall.end_a_local);
        ASSERT_GT(s_m, -0.1) << run.spec.id;
        ASSERT_LT(s_m, (wall.end_b_local - wall.end_a_local).norm() + 0.1) << run.spec.id;
      }
    }
  }
  // The relative transform with the digits of its sub-millimetre σ.
  const pipeline::RelativeMountResult& relative = several.relative.at(0);
  char x_text[64];
  std::snprintf(x_text, sizeof(x_text), "%.5f &#177; %.5f m", relative.mount.from_T_to.x_m,
                std::sqrt(relative.mount.covariance(0, 0)));
  EXPECT_NE(html.find(x_text), std::string::npos) << x_text;

  // Each scanner's own page (ID/report.html) compares its joint mount with that scanner's entry
  // of truth.yaml's simulation.scanners (not the top-level one-scanner truth: it would put
  // front_left's yaw 27° off), names the scanner and links back to the run's page.
  ASSERT_EQ(several.scanners.size(), config.scanners.size());
  for (size_t k = 0; k < several.scanners.size(); ++k) {
    const pipeline::ScannerRun& run = several.scanners[k];
    const sim::SimScanner& truth = config.scanners[k];
    ASSERT_EQ(run.spec.id, truth.id);
    ASSERT_TRUE(run.own.report.truth.has_value()) << run.spec.id;
    // truth.yaml's numbers are written in full: equal but for the degrees' round-off.
    EXPECT_NEAR(run.own.report.truth->x_m, truth.mount_x_m, 1e-12) << run.spec.id;
    EXPECT_NEAR(run.own.report.truth->y_m, truth.mount_y_m, 1e-12) << run.spec.id;
    EXPECT_NEAR(run.own.report.truth->yaw_rad, truth.mount_yaw_rad, 1e-12) << run.spec.id;
    ASSERT_TRUE(run.joint) << run.spec.id;
    const std::string page = outputs::FormatReportHtml(run.own, &*run.joint);
    EXPECT_EQ(XmlProblem(page), "") << run.spec.id;
    testing_support::ExpectContains(
        page, {"<h1>wallcal calibration report: two-corner-scanners, scanner " + run.spec.id +
                   "</h1>",
               "<title>wallcal report: two-corner-scanners, scanner " + run.spec.id + "</title>",
               "<a href=\"../index.html\">"});
  }
}

TEST(SeveralReportTest, AFailedRunStillGivesAWellFormedPage) {
  pipeline::SeveralScannersResult several;
  several.session.name = "two <scanners>";
  pipeline::ScannerRun refused;
  refused.spec.id = "rear";
  refused.spec.frame = "rear";
  refused.own.solve.estimate.message = "the wall was not detected";
  several.scanners.push_back(refused);
  several.outcome = pipeline::SeveralOutcome::kFailed;
  several.message = "mount not determined for scanner 'rear'";
  const std::string html = outputs::FormatSeveralReportHtml(several);
  EXPECT_EQ(XmlProblem(html), "");
  testing_support::ExpectContains(
      html, {"NOT WRITTEN", "REFUSED", "the wall was not detected", "two &lt;scanners&gt;",
             "Nothing to draw"});
}

}  // namespace
}  // namespace wallcal
