// nearcap report's page in a real browser (Debian's chromium, headless): every
// image loads, the page logs nothing to the console, and a screenshot is kept
// under out/report-browser/ of the source tree (its path is printed) for a
// person to look at, also after a CI run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

TEST(ReportBrowser, EveryImageLoadsWithoutAConsoleMessage) {
  if (::access("/usr/bin/chromium", X_OK) != 0)
    GTEST_SKIP() << "no /usr/bin/chromium (Debian: chromium, which scripts/install-deps.sh installs)";
  const fs::path dir = fs::temp_directory_path() / ("nearcap_report_browser_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  test::CliResult r = test::run_cli(
      "sweep --path data/paths/near_plane_sweep.json --samples 6 --seed 2 --width 24 "
      "--height 18 --out " +
          (dir / "rows.csv").string(),
      "browser_sweep");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli(
      "report " + (dir / "rows.csv").string() + " --out " + (dir / "report").string() + " --policy data/policy.json",
      "browser_report");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The harness loads the page in a frame and writes what it found into its own DOM, which chromium dumps.
  {
    std::ofstream f(dir / "harness.html");
    f << "<!doctype html><html><body><iframe id=\"r\" src=\"report/index.html\" width=\"1200\" height=\"800\">"
         "</iframe><script>document.getElementById('r').onload = function () {"
         "const images = Array.from(this.contentDocument.images);"
         "const broken = images.filter(i => !i.complete || i.naturalWidth === 0).map(i => i.getAttribute('src'));"
         "const out = document.createElement('pre'); out.id = 'result';"
         "out.textContent = 'images=' + images.length + ' broken=' + broken.length + ' ' + broken.join(' ');"
         "document.body.appendChild(out); };</script></body></html>";
  }
  // A profile of its own, whatever the version's default: a chromium whose
  // profile another one holds exits (code 21) without loading the page.
  // `timeout` bounds a hang, far above a cold start on a loaded machine.
  const std::string chromium =
      "timeout 300 /usr/bin/chromium --headless=new --no-sandbox --disable-gpu --allow-file-access-from-files "
      "--user-data-dir='" +
      (dir / "profile").string() + "' --virtual-time-budget=10000 --enable-logging=stderr --v=0 ";
  const fs::path dom = dir / "dom.html", log = dir / "chromium.log";
  ASSERT_EQ(std::system((chromium + "--dump-dom 'file://" + (dir / "harness.html").string() + "' > '" + dom.string() +
                         "' 2> '" + log.string() + "'")
                            .c_str()),
            0)
      << test::slurp(log);
  const std::string page = test::slurp(dom);
  const std::size_t at = page.find("<pre id=\"result\">images=");
  ASSERT_NE(at, std::string::npos) << page;
  const std::string result = page.substr(at + 17, page.find("</pre>", at) - at - 17);
  EXPECT_NE(result.find(" broken=0 "), std::string::npos) << result;
  EXPECT_EQ(result.find("images=0 "), std::string::npos) << result;
  // Console messages come as "INFO:CONSOLE(...)" lines; the report has no script, so any is a fault.
  const std::string logged = test::slurp(log);
  EXPECT_EQ(logged.find(":CONSOLE"), std::string::npos) << logged;
  const fs::path shots = fs::path(NEARCAP_SOURCE_DIR) / "out" / "report-browser";
  fs::create_directories(shots);
  const fs::path shot = shots / "report.png";
  ASSERT_EQ(std::system((chromium + "--window-size=1200,6000 --screenshot='" + shot.string() + "' 'file://" +
                         (dir / "report" / "index.html").string() + "' > /dev/null 2>&1")
                            .c_str()),
            0);
  EXPECT_EQ(test::slurp(shot).substr(1, 3), "PNG");
  std::printf("screenshot of the report: %s\n", shot.c_str());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
