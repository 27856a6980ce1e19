// SPDX-License-Identifier: Apache-2.0
// guide --follow --serve's page in a real browser: Debian's Chromium, headless, driven through
// chromedriver (test/support/webdriver_client.h), opens the page while this test grows a
// simulated session's logs in steps (the cuts of sim::CutTextSession, each appended to the
// logs the guide follows). At each step the page must come to show what `wallcal guide --json`
// says on the same logs: the station count, the σ of x, y and yaw (to the digits shown and the
// per cent that a guide reading on from where it stopped differs by, test/guide's
// ReadsATextScanLogOnFromWhereItStopped) and ENOUGH or NOT YET; the last step is enough, and
// the guide then ends by itself. No timing is asserted: each wait is generous (minutes).
//
// Without Chromium (packages chromium, chromium-driver: `bash scripts/install-deps.sh browser`)
// the test is skipped and says so. With WALLCAL_PAGE_SCREENSHOT=FILE.png it also saves the page
// at the middle step (1280×800), as docs/field-guide.md shows it.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "sim/recording_session.h"
#include "sim/session_cut.h"
#include "sim/simulation_config.h"
#include "test/support/background_program.h"
#include "test/support/json_value.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"
#include "test/support/scratch_files.h"
#include "test/support/webdriver_client.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;
using testing_support::Json;
using testing_support::JsonParser;

// The session's steps: shares of its scans (ten stations over the whole).
const std::vector<double> kSteps = {0.15, 0.4, 0.7, 1.0};
// Tolerances the whole session meets and its first part does not (set with the steps above).
const char kTolerances[] = "acceptance:\n  max_sigma_xy_m: 0.015\n  max_sigma_yaw_deg: 0.2\n";

std::string Base64Decode(const std::string& text) {
  std::string out;
  int bits = 0, value = 0;
  for (char c : text) {
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    if (v < 0) continue;
    value = (value << 6) | v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((value >> bits) & 0xff);
    }
  }
  return out;
}

// Appends to each log in `live` what the same log in `cut` has beyond it (the cut of a larger
// share starts with the smaller one's bytes). The pose logs first, the scan log last: a refresh
// between the two sees the new poses with the old scans, as a logger's order would give.
void GrowTo(const fs::path& live, const fs::path& cut) {
  for (const char* name : {"gnss.nmea", "heading.nmea", "scans.clf"}) {
    const std::string now = testing_support::ReadFile(live / name);
    const std::string grown = testing_support::ReadFile(cut / name);
    ASSERT_EQ(grown.compare(0, now.size(), now), 0) << name << ": not a prefix";
    std::ofstream(live / name, std::ios::binary | std::ios::app)
        .write(grown.data() + now.size(), static_cast<std::streamsize>(grown.size() - now.size()));
  }
}

// What the page shows now, as a person reads it.
struct Shown {
  std::string stations, verdict, x, y, yaw, status;
  std::string Text() const {
    return "stations " + stations + ", " + verdict + ", σ x " + x + ", y " + y + ", yaw " + yaw +
           " (" + status + ")";
  }
};

bool ReadPage(testing_support::Browser* browser, Shown* shown) {
  Json value;
  if (!browser->Execute(
          "const t = id => { const e = document.getElementById(id); return e ? e.textContent : ''; };"
          "return {stations: t('stations'), verdict: t('verdict'), x: t('sigma-x'), "
          "y: t('sigma-y'), yaw: t('sigma-yaw'), status: t('status')};",
          &value)) {
    return false;
  }
  shown->stations = value["stations"].text;
  shown->verdict = value["verdict"].text;
  shown->x = value["x"].text;
  shown->y = value["y"].text;
  shown->yaw = value["yaw"].text;
  shown->status = value["status"].text;
  return true;
}

// A σ as shown ("23.7 mm", "0.046°") against guide --json's (m, deg): the shown digits and 2 %.
bool SameSigma(const std::string& shown, const Json& expected, double scale, double digit) {
  if (expected.kind == Json::kNull) return shown == "–";
  const double value = std::strtod(shown.c_str(), nullptr);
  const double want = expected.number * scale;
  return std::abs(value - want) <= 0.6 * digit + 0.02 * std::abs(want);
}

bool Matches(const Shown& shown, const Json& expected) {
  return shown.stations == std::to_string(static_cast<int>(expected["stations"].number)) &&
         shown.verdict == (expected["enough"].b ? "ENOUGH" : "NOT YET") &&
         SameSigma(shown.x, expected["predicted_sigma"]["x_m"], 1000.0, 0.1) &&
         SameSigma(shown.y, expected["predicted_sigma"]["y_m"], 1000.0, 0.1) &&
         SameSigma(shown.yaw, expected["predicted_sigma"]["yaw_deg"], 1.0, 0.001);
}

TEST(GuidePageBrowserTest, ShowsWhatGuideJsonSaysAsTheLogsGrow) {
  const std::string missing = testing_support::BrowserMissing();
  if (!missing.empty()) GTEST_SKIP() << missing;

  const testing_support::ScratchDir scratch("wallcal_guide_page_");
  const fs::path full = scratch.path() / "full", live = scratch.path() / "live";
  sim::WriteSimulatedSession(
      sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml"),
      5, full.string(), sim::SessionFormat::kText);
  std::vector<fs::path> cuts;
  for (size_t k = 0; k < kSteps.size(); ++k) {
    cuts.push_back(scratch.path() / ("cut" + std::to_string(k)));
    sim::CutTextSession(full.string(), cuts.back().string(), kSteps[k]);
  }
  sim::CutTextSession(full.string(), live.string(), kSteps[0]);
  const fs::path tolerances = scratch.path() / "tolerances.yaml";
  std::ofstream(tolerances) << kTolerances;

  testing_support::BackgroundProgram guide(
      {testing_support::WallcalPath(), "guide", live.string(), "--follow", "--json", "--serve",
       "127.0.0.1:0", "--max-seconds", "600", "--config", tolerances.string(), "--threads", "1"},
      scratch.path() / "guide.out", scratch.path() / "guide.err");
  ASSERT_TRUE(guide.started());
  const std::string line = guide.WaitForErrLine("http://", 120.0);
  ASSERT_FALSE(line.empty()) << "the guide printed no URL:\n" << guide.Err();
  const std::string url = line.substr(line.find("http://"));

  testing_support::Browser browser(scratch.path() / "profile", 1280, 800);
  ASSERT_TRUE(browser.ok()) << browser.error();
  ASSERT_TRUE(browser.Navigate(url)) << browser.error();

  const char* screenshot = std::getenv("WALLCAL_PAGE_SCREENSHOT");
  for (size_t k = 0; k < kSteps.size(); ++k) {
    if (k > 0) GrowTo(live, cuts[k]);
    const testing_support::ProgramRun once = testing_support::RunWallcal(
        {"guide", live.string(), "--json", "--config", tolerances.string(), "--threads", "1"});
    ASSERT_EQ(once.exit_code, 0) << once.err;
    Json expected;
    ASSERT_TRUE(JsonParser(once.out).Parse(&expected)) << once.out;
    EXPECT_EQ(expected["enough"].b, k + 1 == kSteps.size()) << "step " << k << ": " << once.out;

    Shown shown;
    bool matched = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (!matched && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      matched = ReadPage(&browser, &shown) && Matches(shown, expected);
    }
    const Json& sigma = expected["predicted_sigma"];
    EXPECT_TRUE(matched) << "step " << k << " (" << kSteps[k] << " of the scans): the page shows "
                         << shown.Text() << "; guide --json says stations "
                         << expected["stations"].number << ", enough " << expected["enough"].b
                         << ", σ x " << sigma["x_m"].number << " m, y " << sigma["y_m"].number
                         << " m, yaw " << sigma["yaw_deg"].number << "°\nthe guide's stderr:\n"
                         << guide.Err();
    if (screenshot != nullptr && k == kSteps.size() / 2) {
      std::this_thread::sleep_for(std::chrono::seconds(1));  // the status line settled
      std::string png;
      ASSERT_TRUE(browser.Screenshot(&png)) << browser.error();
      std::ofstream(screenshot, std::ios::binary) << Base64Decode(png);
    }
  }
  // Enough: the guide ends by itself once the page has fetched that last report.
  int status = -1;
  EXPECT_TRUE(guide.Wait(120.0, &status)) << guide.Err();
  EXPECT_EQ(status, 0) << guide.Err();
}

}  // namespace
}  // namespace wallcal
