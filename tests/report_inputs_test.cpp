// nearcap report's inputs and failures: every input bounded and checked like
// a scene, every failure of the report script one line with exit code 2 and
// nothing written, the tables safe to open in a spreadsheet, and memory that
// does not grow with the rows.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

// A sweep CSV as nearcap writes it: no field is quoted.
struct Rows {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    std::string field;
    while (std::getline(in, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.push_back("");
    return fields;
  }
  static Rows read(const fs::path& p) {
    Rows r;
    std::istringstream in(test::slurp(p));
    std::string line;
    std::getline(in, line);
    r.header = split(line);
    while (std::getline(in, line)) r.rows.push_back(split(line));
    return r;
  }
  std::size_t column(const std::string& name) const {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  }
  static std::string quoted(const std::string& f) {
    if (f.find_first_of(",\"\n") == std::string::npos) return f;
    std::string q = "\"";
    for (char c : f) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  }
  static void write_row(std::ostream& out, const std::vector<std::string>& row) {
    for (std::size_t k = 0; k < row.size(); ++k) out << (k ? "," : "") << quoted(row[k]);
    out << "\n";
  }
  void write(const fs::path& p) const {
    std::ofstream out(p, std::ios::binary);
    write_row(out, header);
    for (const auto& r : rows) write_row(out, r);
  }
};

// Under the sanitizers the tests whose assertions are about the Python
// script's own work (what the page and report.json say, the rows it refuses,
// its memory) are skipped: the C++ they run is the report command's launcher,
// which the other tests here run under the sanitizers; the Release suite runs
// them all (scripts/test.sh).
#if defined(NEARCAP_TESTS_UNDER_ASAN)
#define SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS() GTEST_SKIP() << "the Python script's work: the Release suite checks it"
#else
#define SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS() static_cast<void>(0)
#endif

class ReportInputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("nearcap_report_inputs_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const test::CliResult r = test::run_cli(
        "sweep --path data/paths/near_plane_sweep.json --samples 12 --seed 2 --width 24 --height 18 "
        "--policies all --out " +
            (dir_ / "rows.csv").string(),
        "report_inputs_sweep");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::permissions(dir_ / "readonly", fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }
  static fs::path path(const std::string& name) { return dir_ / name; }
  static std::string rows() { return path("rows.csv").string(); }

  // The command failed with one line "nearcap: error (...)" holding `fragment`, exit code 2.
  static void expect_one_line(const test::CliResult& r, const std::string& fragment, const std::string& what) {
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("nearcap: error (", 0), 0u) << what << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << "\n" << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << what << "\n" << r.err;
  }

  static fs::path dir_;
};
fs::path ReportInputs::dir_;

TEST_F(ReportInputs, ACsvThatIsNotUtf8IsOneLineNamingTheLine) {
  Rows r = Rows::read(rows());
  r.rows[4][r.column("detail")] = "caf\xe9";  // Latin-1
  r.write(path("latin1.csv"));
  const fs::path out = path("never_latin1");
  const test::CliResult result = test::run_cli("report " + path("latin1.csv").string() + " --out " + out.string(), "r");
  expect_one_line(result, "line 6: not UTF-8", "Latin-1 byte");
  EXPECT_NE(result.err.find("error (parse)"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ReportInputs, AnOutThatCannotBeWrittenIsOneLine) {
  // A read-only directory: the permission is enforced for a user other than root.
  const fs::path readonly = path("readonly");
  fs::create_directories(readonly);
  fs::permissions(readonly, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  std::string prefix;
  if (::geteuid() == 0) {
    ASSERT_EQ(::access("/usr/bin/setpriv", X_OK), 0) << "as root this test runs nearcap as nobody with setpriv";
    const fs::path home = path("nobody_home");
    fs::create_directories(home);
    fs::permissions(home, fs::perms::all);
    prefix = "MPLCONFIGDIR=" + home.string() + " XDG_CACHE_HOME=" + home.string() +
             " /usr/bin/setpriv --reuid=65534 --regid=65534 --clear-groups";
  }
  for (const fs::path& out : {readonly, readonly / "sub"}) {
    const test::CliResult r = test::run_cli("report " + rows() + " --out " + out.string(), "ro", prefix);
    expect_one_line(r, "cannot write the report there", out.string());
    EXPECT_NE(r.err.find("error (io)"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(readonly)) << out;
  }
  // A file system that refuses new directories to everyone (sysfs).
  if (fs::exists("/sys/kernel")) {
    const test::CliResult r = test::run_cli("report " + rows() + " --out /sys/nearcap_report_test", "sys");
    expect_one_line(r, "/sys/nearcap_report_test: cannot write the report there", "sysfs");
  }
}

TEST_F(ReportInputs, AFullDiskIsOneLineAndWritesNothing) {
  // RLIMIT_FSIZE stands for a full disk: a write past 50 kB fails (EFBIG; Python ignores SIGXFSZ).
  const fs::path out = path("full");
  const test::CliResult r = test::run_cli("report " + rows() + " --out " + out.string(), "full", "ulimit -f 50;");
  expect_one_line(r, "cannot write the report (", "file size limit");
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().rfind(".nearcap-report-", 0), std::string::npos) << entry.path();
}

TEST_F(ReportInputs, AScriptThatFailsWithoutAnErrorLineIsOneLine) {
  const fs::path out = path("never_script");
  // Python that exits 1 and says nothing.
  test::CliResult r =
      test::run_cli("report " + rows() + " --out " + out.string(), "false", "NEARCAP_PYTHON=/bin/false");
  expect_one_line(r, "exited with status 1", "/bin/false");
  EXPECT_NE(r.err.find("sweep_report.py"), std::string::npos) << r.err;
  // Python killed by a signal.
  const fs::path killed = path("killed.sh");
  {
    std::ofstream f(killed);
    f << "#!/bin/sh\nkill -9 $$\n";
  }
  fs::permissions(killed, fs::perms::owner_all);
  r = test::run_cli("report " + rows() + " --out " + out.string(), "killed", "NEARCAP_PYTHON=" + killed.string());
  expect_one_line(r, "killed by signal 9", "SIGKILL");
  // A script that stops on an exception: the traceback goes to the log the line names.
  const fs::path raising = path("raising.py");
  {
    std::ofstream f(raising);
    f << "raise RuntimeError('the report script broke')\n";
  }
  r = test::run_cli("report " + rows() + " --out " + out.string(), "raising",
                    "NEARCAP_REPORT_SCRIPT=" + raising.string());
  expect_one_line(r, "exited with status 1", "traceback");
  const std::string marker = "its output is in ";
  const std::size_t at = r.err.find(marker);
  ASSERT_NE(at, std::string::npos) << r.err;
  const fs::path log = r.err.substr(at + marker.size(), r.err.size() - at - marker.size() - 1);
  const std::string logged = test::slurp(log);
  EXPECT_NE(logged.find("Traceback"), std::string::npos) << logged;
  EXPECT_NE(logged.find("the report script broke"), std::string::npos) << logged;
  fs::remove(log);
  EXPECT_FALSE(fs::exists(out));
}

// A script or Python that exits 0 without writing DIR/index.html is an
// error, not a report: with nothing there, and with an earlier report's page
// left as it was; a script that is not a regular file is refused.
TEST_F(ReportInputs, AScriptThatWritesNoPageIsAnError) {
  const fs::path out = path("nothing_written");
  test::CliResult r = test::run_cli("report " + rows() + " --out " + out.string(), "true", "NEARCAP_PYTHON=/bin/true");
  expect_one_line(r, "exited with status 0 (NEARCAP_PYTHON=/bin/true) without writing " + (out / "index.html").string(),
                  "/bin/true");
  fs::create_directories(out);
  std::ofstream(out / "index.html") << "an earlier report";
  r = test::run_cli("report " + rows() + " --out " + out.string(), "true_stale", "NEARCAP_PYTHON=/bin/true");
  expect_one_line(r, "without writing", "/bin/true over an earlier report");
  EXPECT_EQ(test::slurp(out / "index.html"), "an earlier report");
  // A Python that warns and writes nothing: one line, naming the log that holds the warning.
  const fs::path warns = path("warns.sh");
  std::ofstream(warns) << "#!/bin/sh\necho 'UserWarning: something odd' >&2\nexit 0\n";
  fs::permissions(warns, fs::perms::owner_all);
  r = test::run_cli("report " + rows() + " --out " + path("warned").string(), "warns",
                    "NEARCAP_PYTHON=" + warns.string());
  expect_one_line(r, "exited with status 0 (NEARCAP_PYTHON=" + warns.string() + ") without writing ", "a warning");
  const std::string marker = "its output is in ";
  ASSERT_NE(r.err.find(marker), std::string::npos) << r.err;
  const fs::path log =
      r.err.substr(r.err.find(marker) + marker.size(), r.err.size() - r.err.find(marker) - marker.size() - 1);
  EXPECT_NE(test::slurp(log).find("something odd"), std::string::npos);
  fs::remove(log);
  r = test::run_cli("report " + rows() + " --out " + path("device_script").string(), "device_script",
                    "NEARCAP_REPORT_SCRIPT=/dev/null");
  expect_one_line(r, "/dev/null: the report script is not a regular file", "/dev/null");
}

// A CSV named outside UTF-8 is reported, its name escaped in the page; an
// --out name too long for the file system is one line.
TEST_F(ReportInputs, OddNamesAreReportedOrRefusedInOneLine) {
  const fs::path odd = path("latin\xff.csv");
  fs::copy_file(rows(), odd, fs::copy_options::overwrite_existing);
  const fs::path out = path("odd_name");
  const test::CliResult r = test::run_cli("report '" + odd.string() + "' --out " + out.string(), "odd_name");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::slurp(out / "index.html").find("latin\\xff.csv"), std::string::npos);
  const std::string long_name = path(std::string(300, 'a')).string();
  expect_one_line(test::run_cli("report " + rows() + " --out " + long_name, "long_name"), "File name too long",
                  "a 300-byte name");
}

// A file name's control characters and bytes outside UTF-8 are escaped in
// the line, as nearcap's own errors write them (io/utf8_text.hpp).
TEST_F(ReportInputs, AFileNameInTheErrorIsEscaped) {
  Rows r = Rows::read(rows());
  r.rows[4].pop_back();  // one field short
  for (const auto& [name, shown] : {std::pair<std::string, std::string>{"line\nfeed.csv", "line\\nfeed.csv"},
                                    {"tab\tand\x7f.csv", "tab\\tand\\x7f.csv"},
                                    {"latin\xff.csv", "latin\\xff.csv"}}) {
    r.write(path(name));
    const test::CliResult result =
        test::run_cli("report '" + path(name).string() + "' --out " + path("never_named").string(), "named");
    expect_one_line(result, shown + ": line 6:", shown);
    EXPECT_FALSE(fs::exists(path("never_named")));
    fs::remove(path(name));
  }
}

// What the report prints at the end cannot be written (stdout a full
// device): one line saying so, exit code 2, not a failure of the script.
TEST_F(ReportInputs, AFullStandardOutputIsOneLine) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string command = "'" + std::string(NEARCAP_CLI) + "' report " + rows() + " --out " +
                              path("to_full").string() + " > /dev/full 2> " + path("full_err.txt").string();
  const int status = std::system(command.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
  const std::string err = test::slurp(path("full_err.txt"));
  EXPECT_EQ(err.rfind("nearcap: error (io): standard output: cannot write what the command printed", 0), 0u) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST_F(ReportInputs, TheInputLimitAppliesToTheCsvsAndThePolicy) {
  const std::string text = test::slurp(rows());
  {
    std::ofstream f(path("big.csv"));
    while (f.tellp() < (3 << 19)) f << text;  // over 1 MB
  }
  {
    std::ofstream f(path("big_policy.json"));
    f << test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json") << std::string(3 << 19, ' ');
  }
  const fs::path out = path("never_limit");
  test::CliResult r =
      test::run_cli("report " + path("big.csv").string() + " --out " + out.string(), "limit", "NEARCAP_MAX_INPUT_MB=1");
  expect_one_line(r, "over the input limit of 1 MB", "big CSV");
  EXPECT_NE(r.err.find("error (resource)"), std::string::npos) << r.err;
  r = test::run_cli("report " + rows() + " --policy " + path("big_policy.json").string() + " --out " + out.string(),
                    "limit", "NEARCAP_MAX_INPUT_MB=1");
  expect_one_line(r, "over the input limit of 1 MB", "big policy");
  EXPECT_NE(r.err.find("big_policy.json"), std::string::npos) << r.err;
  r = test::run_cli("report " + rows() + " --out " + out.string(), "limit", "NEARCAP_MAX_INPUT_MB=lots");
  expect_one_line(r, "NEARCAP_MAX_INPUT_MB", "bad variable");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ReportInputs, InputsThatAreNotRegularFilesAreRefused) {
  const fs::path fifo = path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path out = path("never_fifo");
  // `timeout`: a FIFO read would block for ever.
  test::CliResult r = test::run_cli("report " + fifo.string() + " --out " + out.string(), "fifo", test::kHangBound);
  expect_one_line(r, "not a regular file", "FIFO CSV");
  r = test::run_cli("report " + rows() + " --policy " + fifo.string() + " --out " + out.string(), "fifo",
                    test::kHangBound);
  expect_one_line(r, "a FIFO", "FIFO policy");
  r = test::run_cli("report " + rows() + " --policy /dev/zero --out " + out.string(), "zero", test::kHangBound);
  expect_one_line(r, "a character device", "/dev/zero policy");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ReportInputs, APolicyOfAnUnknownVersionIsRefused) {
  nlohmann::json policy = nlohmann::json::parse(test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json"));
  policy["version"] = 99;
  {
    std::ofstream f(path("v99.json"));
    f << policy.dump(1);
  }
  const fs::path out = path("never_v99");
  const test::CliResult r =
      test::run_cli("report " + rows() + " --policy " + path("v99.json").string() + " --out " + out.string(), "v99");
  expect_one_line(r, "99 is not a version this nearcap reads", "version 99");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ReportInputs, PathsWhoseNamesWouldShareAFileGetAPlotEach) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  const Rows all = Rows::read(rows());
  Rows two{all.header, {}};
  const std::size_t configuration = all.column("configuration"), kind = all.column("kind");
  for (const std::string name : {"a,b", "a b"})
    for (std::vector<std::string> row : all.rows) {
      if (row[configuration].rfind("path:", 0) != 0) continue;
      row[configuration] = "path:" + name + ":" + row[configuration].substr(row[configuration].rfind(':') + 1);
      row[kind] = name;
      two.rows.push_back(row);
    }
  two.write(path("two_paths.csv"));
  const fs::path out = path("two_paths");
  const test::CliResult r = test::run_cli("report " + path("two_paths.csv").string() + " --out " + out.string(), "ab");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json manifest = nlohmann::json::parse(test::slurp(out / "report.json"));
  std::set<std::string> path_plots;
  for (const auto& plot : manifest["plots"])
    if (plot["file"].get<std::string>().rfind("path_", 0) == 0) path_plots.insert(plot["file"].get<std::string>());
  EXPECT_EQ(path_plots.size(), 2u) << manifest.dump();
  const std::string page = test::slurp(out / "index.html");
  for (const std::string& png : path_plots) {
    EXPECT_TRUE(fs::exists(out / png)) << png;
    EXPECT_NE(page.find("src=\"" + png + "\""), std::string::npos) << png;
  }
}

// The noise floor (Z-pass's frame timed twice: frame_again_ms over frame_ms)
// is stated beside the Pareto plot, drawn on each path's plot and written to
// report.json; without the second timings (a sweep without Z-pass, or a CSV
// without the column) the page says that none was measured.
TEST_F(ReportInputs, TheNoiseFloorIsStatedWhereMeasuredAndItsAbsenceSaid) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  const Rows all = Rows::read(rows());
  const std::size_t method = all.column("method"), again = all.column("frame_again_ms");
  ASSERT_LT(again, all.header.size());
  std::size_t pairs = 0;
  for (const auto& row : all.rows) pairs += row.size() > again && row[method] == "zpass" && !row[again].empty();
  ASSERT_GT(pairs, 60u);

  const fs::path measured = path("noise_measured");
  ASSERT_EQ(test::run_cli("report " + rows() + " --out " + measured.string(), "noise").exit_code, 0);
  const nlohmann::json floor = nlohmann::json::parse(test::slurp(measured / "report.json"))["noise_floor"];
  ASSERT_TRUE(floor.is_object()) << floor.dump();
  EXPECT_EQ(floor["pairs"].get<std::size_t>(), pairs);
  EXPECT_GT(floor["p5"].get<double>(), 0);
  EXPECT_LE(floor["p5"].get<double>(), floor["median"].get<double>());
  EXPECT_LE(floor["median"].get<double>(), floor["p95"].get<double>());
  EXPECT_GT(floor["mean_ratio"].get<double>(), 0);
  ASSERT_TRUE(floor["paths"]["near_plane_sweep"].is_object()) << floor.dump();
  EXPECT_EQ(floor["paths"]["near_plane_sweep"]["pairs"], 60);
  const std::string page = test::slurp(measured / "index.html");
  EXPECT_NE(
      page.find("Noise floor (Z-pass&#x27;s frame timed twice in the same sweep, " + std::to_string(pairs) + " pairs)"),
      std::string::npos)
      << page;
  EXPECT_EQ(page.find("No noise floor was measured"), std::string::npos);

  // The column empty, then the column gone: no noise floor, and the page says so.
  Rows empty = all, gone = all;
  for (auto& row : empty.rows)
    if (row.size() > again) row[again] = "";
  gone.header.erase(gone.header.begin() + static_cast<std::ptrdiff_t>(again));
  for (auto& row : gone.rows)
    if (row.size() > again) row.erase(row.begin() + static_cast<std::ptrdiff_t>(again));
  for (const auto& [name, rows_] : {std::pair<std::string, const Rows&>{"noise_empty", empty}, {"noise_gone", gone}}) {
    rows_.write(path(name + ".csv"));
    const fs::path out = path(name);
    const test::CliResult r = test::run_cli("report " + path(name + ".csv").string() + " --out " + out.string(), name);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_TRUE(nlohmann::json::parse(test::slurp(out / "report.json"))["noise_floor"].is_null()) << name;
    const std::string unmeasured = test::slurp(out / "index.html");
    EXPECT_NE(unmeasured.find("No noise floor was measured"), std::string::npos) << name;
    EXPECT_EQ(unmeasured.find("Noise floor (Z-pass"), std::string::npos) << name;
  }
}

TEST_F(ReportInputs, TablesAreSafeInASpreadsheetAndThePageIsEscaped) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  Rows r = Rows::read(rows());
  const std::size_t configuration = r.column("configuration"), kind = r.column("kind"), method = r.column("method");
  // Three sampled configurations get hostile kinds, one method a hostile name.
  const std::vector<std::string> kinds = {"=HYPERLINK(\"http://x\",\"y\")", "@SUM(A1)", "<b>bold</b>"};
  std::vector<std::string> configurations;
  for (auto& row : r.rows) {
    if (row[configuration].rfind("sample:", 0) != 0) continue;
    auto at = std::find(configurations.begin(), configurations.end(), row[configuration]);
    if (at == configurations.end()) {
      if (configurations.size() == kinds.size()) break;
      configurations.push_back(row[configuration]);
      at = configurations.end() - 1;
    }
    row[kind] = kinds[static_cast<std::size_t>(at - configurations.begin())];
    if (row[method] == "ogre") row[method] = "-2+cmd|' /C calc'!A0";
  }
  ASSERT_EQ(configurations.size(), kinds.size());
  r.write(path("hostile.csv"));
  const fs::path out = path("hostile");
  const test::CliResult result =
      test::run_cli("report " + path("hostile.csv").string() + " --out " + out.string(), "hostile");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const auto& entry : fs::directory_iterator(out)) {
    if (entry.path().extension() != ".csv") continue;
    std::istringstream lines(test::slurp(entry.path()));
    std::string line;
    while (std::getline(lines, line)) {
      ASSERT_FALSE(line.empty());
      const char first = line[0] == '"' && line.size() > 1 ? line[1] : line[0];
      EXPECT_EQ(std::string("=+-@\t\r").find(first), std::string::npos) << entry.path() << ": " << line;
    }
  }
  const std::string by_kind = test::slurp(out / "by_kind.csv");
  EXPECT_NE(by_kind.find("\n\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\","), std::string::npos) << by_kind;
  EXPECT_NE(by_kind.find("\n'@SUM(A1),"), std::string::npos) << by_kind;
  EXPECT_NE(test::slurp(out / "summary.csv").find("\n'-2+cmd|' /C calc'!A0,"), std::string::npos);
  const std::string page = test::slurp(out / "index.html");
  EXPECT_EQ(page.find("<b>bold</b>"), std::string::npos);
  EXPECT_NE(page.find("&lt;b&gt;bold&lt;/b&gt;"), std::string::npos);
  // Negative numbers stay numbers (policy_cost.csv's "+%" columns are signed).
  EXPECT_EQ(test::slurp(out / "summary.csv").find("'-0"), std::string::npos);
}

TEST_F(ReportInputs, AnOutWhoseFilesWouldReplaceAnInputIsRefused) {
  const fs::path out = path("replace");
  fs::create_directories(out);
  fs::copy_file(rows(), out / "summary.csv");
  const std::string before = test::slurp(out / "summary.csv");
  const test::CliResult r =
      test::run_cli("report " + (out / "summary.csv").string() + " --out " + out.string(), "replace");
  expect_one_line(r, "which is its input", "summary.csv in --out");
  EXPECT_EQ(test::slurp(out / "summary.csv"), before);
  EXPECT_EQ(std::distance(fs::directory_iterator(out), fs::directory_iterator()), 1);
}

TEST_F(ReportInputs, AConfigurationWhoseRowsAreApartIsNamed) {
  Rows r = Rows::read(rows());
  const std::size_t configuration = r.column("configuration");
  // The first configuration's last row moved to the end of the file.
  std::size_t last = 0;
  while (r.rows[last + 1][configuration] == r.rows[0][configuration]) ++last;
  const std::vector<std::string> moved = r.rows[last];
  r.rows.erase(r.rows.begin() + static_cast<std::ptrdiff_t>(last));
  r.rows.push_back(moved);
  r.write(path("apart.csv"));
  const fs::path out = path("never_apart");
  const test::CliResult result = test::run_cli("report " + path("apart.csv").string() + " --out " + out.string(), "ap");
  expect_one_line(result, "again after other configurations (first: " + path("apart.csv").string() + " line 2)",
                  "rows apart");
  EXPECT_NE(result.err.find("line " + std::to_string(r.rows.size() + 1) + ":"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(out));
}

// A row whose field count is not the header's is refused naming its line, as
// `nearcap tune` refuses it: a last line cut off inside a column (a sweep
// killed mid-write, no newline at its end), a row with a field too many, a
// `rejected` row cut short, and a quoted field left open at the end.
TEST_F(ReportInputs, ARowWhoseFieldCountIsNotTheHeadersIsRefused) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  const Rows all = Rows::read(rows());
  // reference_ms: the last column the report reads, three before the last.
  const std::size_t width = all.header.size(), reference = all.column("reference_ms"), method = all.column("method");
  ASSERT_LT(reference + 1, width);
  std::string text = test::slurp(rows());
  ASSERT_EQ(text.back(), '\n');
  text.pop_back();
  const std::size_t last_start = text.rfind('\n') + 1;
  const std::string last_line = text.substr(last_start);
  const std::size_t last = 1 + static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  // The last line cut inside reference_ms: its first characters are a
  // number ("0.2" of "0.2782"), the row one of reference + 1 fields.
  std::size_t at = 0;
  for (std::size_t k = 0; k < reference; ++k) at = last_line.find(',', at) + 1;
  const std::size_t value_length = last_line.find(',', at) - at;
  ASSERT_GE(value_length, 3u) << last_line;
  const std::string cut = text.substr(0, last_start) + last_line.substr(0, at + value_length - 2);

  Rows extra = all, rejected = all;
  extra.rows[3].push_back("0");
  rejected.rows[3][method] = "rejected";
  rejected.rows[3].pop_back();
  const std::string quoted = text.substr(0, last_start) + last_line.substr(0, last_line.rfind(',') + 1) + "\"12";
  // The same on line 4, the rest of the file after it: named by the line it opens on.
  std::size_t line4 = 0;
  for (int k = 0; k < 3; ++k) line4 = text.find('\n', line4) + 1;
  const std::size_t line4_end = text.find('\n', line4);
  const std::string row4 = text.substr(line4, line4_end - line4);
  const std::string quoted_mid =
      text.substr(0, line4) + row4.substr(0, row4.rfind(',') + 1) + "\"12" + text.substr(line4_end) + "\n";

  const std::tuple<std::string, std::string, std::string> cases[] = {
      {"cut", cut,
       "line " + std::to_string(last) + ": " + std::to_string(reference + 1) + " fields, the header has " +
           std::to_string(width)},
      {"extra", "", "line 5: " + std::to_string(width + 1) + " fields, the header has " + std::to_string(width)},
      {"rejected", "", "line 5: " + std::to_string(width - 1) + " fields, the header has " + std::to_string(width)},
      {"quoted", quoted, "line " + std::to_string(last) + ": a quoted field is not closed"},
      {"quoted_mid", quoted_mid, "line 4: a quoted field is not closed"},
  };
  for (const auto& [name, body, fragment] : cases) {
    const fs::path csv = path("fields_" + name + ".csv");
    if (name == "extra")
      extra.write(csv);
    else if (name == "rejected")
      rejected.write(csv);
    else
      std::ofstream(csv, std::ios::binary) << body;
    const fs::path out = path("never_fields_" + name);
    const test::CliResult r = test::run_cli("report " + csv.string() + " --out " + out.string(), "fields_" + name);
    expect_one_line(r, csv.string() + ": " + fragment, name);
    EXPECT_EQ(r.err.rfind("nearcap: error (parse): ", 0), 0u) << name << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << name;
  }
}

// A policy that starts with a UTF-8 byte order mark is read, as every other
// command reads it (nearcap's JSON reader skips the mark).
TEST_F(ReportInputs, APolicyWithAByteOrderMarkIsRead) {
  const std::string policy = test::slurp(fs::path(NEARCAP_SOURCE_DIR) / "data" / "policy.json");
  ASSERT_NE(policy.rfind("\xEF\xBB\xBF", 0), 0u);
  std::ofstream(path("bom_policy.json"), std::ios::binary) << "\xEF\xBB\xBF" << policy;
  const fs::path out = path("bom_policy");
  const test::CliResult r = test::run_cli(
      "report " + rows() + " --policy " + path("bom_policy.json").string() + " --out " + out.string(), "bom");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_NE(test::slurp(out / "index.html").find("From <code>" + path("bom_policy.json").string() + "</code>"),
            std::string::npos);
}

// A sweep CSV saved by a spreadsheet starts with a byte order mark: read past,
// it is the same report.
TEST_F(ReportInputs, ASweepCsvWithAByteOrderMarkIsRead) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  std::ofstream(path("bom_rows.csv"), std::ios::binary) << "\xEF\xBB\xBF" << test::slurp(rows());
  const test::CliResult r =
      test::run_cli("report " + path("bom_rows.csv").string() + " --out " + path("bom_rows").string(), "bom rows");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  EXPECT_TRUE(fs::exists(path("bom_rows") / "index.html"));
}

TEST_F(ReportInputs, MemoryDoesNotGrowWithTheRows) {
  SKIP_THE_SCRIPTS_WORK_UNDER_SANITIZERS();
  if (::access("/usr/bin/time", X_OK) != 0) GTEST_SKIP() << "/usr/bin/time (Debian: time) measures the peak memory";
  // 150,000 rows: the sampled configurations copied under new names.  Holding
  // every row as a dict took about 3.6 kB a row (over 500 MB here); streamed,
  // the report's peak is matplotlib's plus a bounded sample of scatter points.
  const Rows r = Rows::read(rows());
  const std::size_t configuration = r.column("configuration");
  const fs::path big = path("many.csv");
  std::size_t written = 0;
  {
    std::ofstream out(big, std::ios::binary);
    Rows::write_row(out, r.header);
    for (int copy = 0; written < 150000; ++copy)
      for (std::vector<std::string> row : r.rows) {
        if (row[configuration].rfind("sample:", 0) != 0) continue;
        row[configuration] = "sample:" + std::to_string(copy) + ":" + row[configuration].substr(7);
        Rows::write_row(out, row);
        ++written;
      }
  }
  const fs::path out = path("many"), peak = path("many.time");
  const test::CliResult result = test::run_cli("report " + big.string() + " --out " + out.string(), "many",
                                               "/usr/bin/time -f %M -o " + peak.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const long kilobytes = std::stol(test::slurp(peak));
  std::printf("report on %zu rows: peak resident set %ld MB\n", written, kilobytes >> 10);
  EXPECT_LT(kilobytes, 300L << 10) << "peak resident set of the report on " << written << " rows";
  const nlohmann::json manifest = nlohmann::json::parse(test::slurp(out / "report.json"));
  EXPECT_EQ(manifest["rows"].get<std::size_t>(), written);
  fs::remove(big);
}

}  // namespace
}  // namespace nearcap
