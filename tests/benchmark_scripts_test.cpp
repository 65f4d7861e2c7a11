// The helper scripts of analysis/benchmarks/ (the tables of docs/findings/):
// bad input is one line on stderr, "nearcap: error (KIND): SCRIPT: ...",
// exit 2, never a traceback or a hang (script_errors.py, script_errors.sh).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace nearcap {
namespace {

namespace fs = std::filesystem;

TEST(BenchmarkScripts, BadInputIsOneLineNeverATraceback) {
  const fs::path dir = test::temp_path("nearcap_benchmark_scripts");
  fs::remove_all(dir);
  fs::create_directories(dir / "empty");
  const auto d = [&](const std::string& name) { return "'" + (dir / name).string() + "'"; };
  std::ofstream(dir / "binary.csv") << "\xff\xfe\n";
  std::ofstream(dir / "other.csv") << "a,b\n1,2\n";
  std::ofstream(dir / "header.csv") << "record,frame,kind,triangles,fragments,ms,in_view\n";
  std::ofstream(dir / "other.json") << "{\"x\": 1}\n";
  std::ofstream(dir / "deep.json") << std::string(100000, '[') << std::string(100000, ']') << "\n";
  std::ofstream(dir / "frameless.json") << "{\"methods\": [{\"method\": \"zpass\", \"frames\": [{\"ms\": 1}]}]}\n";
  std::ofstream(dir / "counts.csv") << "configuration,light,variant,method,cracks,wrong,refused\nc,0,,zfail,x,0,0\n";
  const std::string evaluation_header = "set,configuration,frame,light,rule,end_to_end_ms,predicted_ms\n";
  std::ofstream(dir / "eval-header.csv") << evaluation_header;
  std::ofstream(dir / "eval.csv") << evaluation_header << "s,c,,0,policy,1.0,1.1\ns,c,,0,zfail,1.0,\n";
  std::ofstream(dir / "eval-other-set.csv") << evaluation_header << "t,c,,0,policy,1.0,1.1\n";
  std::ofstream(dir / "eval-other-frames.csv") << evaluation_header << "s,d,,0,policy,1.0,1.1\n";
  // Builds whose nearcap fails: with nearcap's own error line after progress
  // on stderr (the script passes its kind and message on, also where the
  // program's buffered stdout comes out after it), and with another failure.
  const auto stub = [&](const std::string& folder, const std::string& body) {
    fs::create_directories(dir / folder);
    std::ofstream(dir / folder / "nearcap") << "#!/bin/sh\n" << body;
    fs::permissions(dir / folder / "nearcap", fs::perms::owner_all);
  };
  stub("failing",
       "echo 'sweep: 1/40 configurations' >&2\necho 'nearcap: error (io): x/rows.csv: cannot write it' >&2\n"
       "echo 'sweep: a summary'\nexit 2\n");
  stub("crashing", "echo boom >&2\nexit 3\n");
  stub("silent", "exit 5\n");
  stub("rateless", "echo 'sweep: done'\n");
  const std::string build = "'" + fs::path(NEARCAP_CLI).parent_path().string() + "'";
  ASSERT_EQ(fs::path(NEARCAP_CLI).filename(), "nearcap") << "the shell scripts run BUILD_DIR/nearcap";
  const char* env = std::getenv("NEARCAP_PYTHON");
  const std::string python = env && *env ? env : "/usr/bin/python3";
  // {script and arguments, the error's kind, a fragment of its message}
  const std::array<std::string, 3> cases[] = {
      {"cap_cpu_table.py", "usage", "usage: cap_cpu_table.py"},
      {"cap_cpu_table.py " + d("missing.json") + " L", "io", "cannot read it"},
      {"cap_cpu_table.py " + d("binary.csv") + " L", "parse", "not a render.json"},
      {"cap_cpu_table.py " + d("other.json") + " L", "schema", "no methods list"},
      {"cap_cpu_table.py " + d("deep.json") + " L", "parse", "not a render.json"},
      {"cap_cpu_table.py " + d("other.json") + " L a b", "usage", "not whole numbers"},
      // What none of the script's own checks names: script_errors.run()'s one line.
      {"cap_cpu_table.py " + d("frameless.json") + " L", "schema", "missing or of the wrong type (KeyError: 'frame')"},
      {"code_footprint.py", "usage", "usage: code_footprint.py"},
      {"code_footprint.py " + d("missing"), "io", "cannot read it"},
      {"code_footprint.py " + d("other.csv"), "parse", "no cost line"},
      {"code_footprint.py " + d("other.csv") + " x", "usage", "not a whole number"},
      {"compare_sweep_rows.py " + d("other.csv"), "usage", "usage: compare_sweep_rows.py"},
      {"compare_sweep_rows.py " + d("missing.csv") + " " + d("other.csv"), "io", "cannot read it"},
      {"compare_sweep_rows.py " + d("binary.csv") + " " + d("other.csv"), "parse", "not a sweep CSV"},
      {"compare_sweep_rows.py " + d("other.csv") + " " + d("other.csv"), "schema", "no column configuration"},
      {"cracks_against_zfail.py", "usage", "usage: cracks_against_zfail.py"},
      {"cracks_against_zfail.py " + d("missing.csv"), "io", "cannot read it"},
      {"cracks_against_zfail.py " + d("binary.csv"), "parse", "not a sweep CSV"},
      {"cracks_against_zfail.py " + d("other.csv"), "schema", "not a sweep CSV with rows"},
      {"cracks_against_zfail.py " + d("counts.csv"), "parse", "'x' is not a count"},
      {"frame_against_passes.py", "usage", "usage: frame_against_passes.py"},
      {"frame_against_passes.py " + d("missing.csv"), "io", "cannot read it"},
      {"frame_against_passes.py " + d("binary.csv"), "parse", "not a calibration CSV"},
      {"frame_against_passes.py " + d("other.csv"), "schema", "no column 'record'"},
      {"frame_price_residuals.py " + d("header.csv"), "usage", "usage: frame_price_residuals.py"},
      {"frame_price_residuals.py " + d("missing.csv") + " data/policy.json", "io", "cannot read it"},
      {"frame_price_residuals.py " + d("binary.csv") + " data/policy.json", "parse", "not a calibration CSV"},
      {"frame_price_residuals.py " + d("header.csv") + " data/policy.json", "schema", "frame rows of two methods"},
      {"frame_price_residuals.py " + d("header.csv") + " " + d("other.json"), "schema", "without a device profile"},
      {"frame_price_residuals.py " + d("header.csv") + " " + d("deep.json"), "parse", "not a policy file"},
      {"in_view_fit.py", "usage", "usage: in_view_fit.py"},
      {"in_view_fit.py " + d("missing.csv"), "io", "cannot read it"},
      {"in_view_fit.py " + d("binary.csv"), "parse", "not a calibration CSV"},
      {"in_view_fit.py " + d("header.csv"), "schema", "no pass row"},
      {"prediction_floor.py " + d("eval.csv"), "usage", "usage: prediction_floor.py"},
      {"prediction_floor.py " + d("missing.csv") + " " + d("eval.csv"), "io", "cannot read it"},
      {"prediction_floor.py " + d("binary.csv") + " " + d("eval.csv"), "parse", "not an evaluation CSV"},
      {"prediction_floor.py " + d("other.csv") + " " + d("eval.csv"), "schema", "no column 'set'"},
      {"prediction_floor.py " + d("eval-header.csv") + " " + d("eval.csv"), "schema", "no policy row"},
      {"prediction_floor.py " + d("eval.csv") + " " + d("eval-other-set.csv"), "schema",
       "no set is in two of the runs"},
      {"prediction_floor.py " + d("eval.csv") + " " + d("eval-other-frames.csv"), "schema", "holds other frames"},
      {"prediction_floor.py " + d("eval.csv") + " " + d("eval.csv"), "schema",
       "fewer than two frames with Z-fail's time"},
      {"raytrace_hard_cases.py --samples x", "usage", "invalid int value"},
      {"raytrace_hard_cases.py --samples 1 --nearcap " + d("missing"), "io", "No such file"},
      {"raytrace_hard_cases.py --samples 1 --nearcap /bin/false", "io", "sample --seed 1 --index 0 failed"},
      {"volume_culling_fragments.py", "usage", "usage: volume_culling_fragments.py"},
      {"volume_culling_fragments.py " + d("empty"), "io", "paths-none.csv: cannot read it"},
      // The shell ones (script_errors.sh), BUILD_DIR the folder of the nearcap under test.
      {"sweep_rates.sh " + d("empty"), "usage", "nearcap: no such program"},
      {"sweep_rates.sh " + d("failing"), "io", "sweep_rates.sh: x/rows.csv: cannot write it"},
      {"sweep_rates.sh " + d("crashing"), "unavailable", "nearcap sweep failed (exit status 3): boom"},
      {"sweep_rates.sh " + d("silent"), "unavailable",
       "nearcap sweep failed (exit status 5), printing nothing on stderr"},
      {"orbit_against_build.sh " + build, "usage", "usage: orbit_against_build.sh BUILD_DIR OTHER_BUILD_DIR"},
      {"orbit_against_build.sh " + build + " " + d("empty"), "usage", "nearcap: no such program"},
      {"orbit_against_build.sh " + build + " " + build + " 0", "usage", "'0' is not a positive whole number"},
      {"orbit_against_build.sh " + d("failing") + " " + build, "io", "x/rows.csv: cannot write it"},
      {"orbit_against_build.sh " + d("rateless") + " " + build, "parse", "no rate in its closing line: sweep: done"},
      {"orbit_instructions.sh " + d("empty"), "usage", "nearcap: no such program"},
      {"orbit_instructions.sh " + build + " x", "usage", "'x' is not a positive whole number"},
      {"decision_instructions.sh " + build + " " + d("missing.json"), "io", "missing.json: no such path file"},
      {"unit_compile_time.sh", "usage", "usage: unit_compile_time.sh OBJECT LEVEL"},
  };
  for (const auto& [args, kind, fragment] : cases) {
    const std::string script = args.substr(0, args.find(' '));
    // A shell script runs as findings.sh runs it, under its own #! (sh or bash).
    const bool shell = script.size() > 3 && script.compare(script.size() - 3, 3, ".sh") == 0;
    const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && " + test::kHangBound + " " +
                                (shell ? std::string() : "'" + python + "' ") + "analysis/benchmarks/" + args +
                                " > /dev/null 2> " + d("err.txt");
    const int status = std::system(command.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << args;
    const std::string err = test::slurp(dir / "err.txt");
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << args << "\n" << err;
    EXPECT_EQ(err.rfind("nearcap: error (" + kind + "): " + script + ": ", 0), 0u) << args << "\n" << err;
    EXPECT_NE(err.find(fragment), std::string::npos) << args << "\n" << err;
    EXPECT_EQ(err.find("Traceback"), std::string::npos) << args << "\n" << err;
  }
  // script_errors.sh under dash (unit_compile_time.sh's #!): a backslash in
  // the message is printed as it is, not read as an escape.
  const std::string dash = "cd '" + std::string(NEARCAP_SOURCE_DIR) +
                           "' && sh -c '. analysis/benchmarks/script_errors.sh; fail usage \"a\\\\cb\"' x.sh 2> " +
                           d("err.txt");
  const int status = std::system(dash.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
  EXPECT_EQ(test::slurp(dir / "err.txt"), "nearcap: error (usage): x.sh: a\\cb\n");
  // quietly: a command that succeeds says nothing; one that fails stops the
  // script with the last line of its output, nearcap's kind kept.
  const std::string quietly = "cd '" + std::string(NEARCAP_SOURCE_DIR) +
                              "' && sh -c '. analysis/benchmarks/script_errors.sh; quietly echo said; echo ran; "
                              "quietly \"$1\" sweep; echo after' x.sh " +
                              d("failing/nearcap") + " > " + d("out.txt") + " 2> " + d("err.txt");
  const int quietly_status = std::system(quietly.c_str());
  EXPECT_EQ(WIFEXITED(quietly_status) ? WEXITSTATUS(quietly_status) : -1, 2);
  EXPECT_EQ(test::slurp(dir / "out.txt"), "ran\n");
  EXPECT_EQ(test::slurp(dir / "err.txt"), "nearcap: error (io): x.sh: x/rows.csv: cannot write it\n");
  fs::remove_all(dir);
}

// Valid input keeps its meaning: compare_sweep_rows.py exits 0 when the rows
// match but for the times (columns ending in _ms), 1 when any other cell
// differs, as the "identical rows" checks read it.
TEST(BenchmarkScripts, CompareSweepRowsExitsOneOnlyWhereACellOtherThanATimeDiffers) {
  const fs::path dir = test::temp_path("nearcap_compare_rows");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string header = "configuration,light,method,variant,wrong,frame_ms\n";
  std::ofstream(dir / "a.csv") << header << "c,0,zpass,,3,1.5\nc,0,zfail,,0,2.0\n";
  std::ofstream(dir / "times.csv") << header << "c,0,zfail,,0,9.0\nc,0,zpass,,3,7.5\n";
  std::ofstream(dir / "wrong.csv") << header << "c,0,zpass,,4,1.5\nc,0,zfail,,0,2.0\n";
  const auto status = [&](const std::string& other) {
    const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) +
                                "' && python3 analysis/benchmarks/compare_sweep_rows.py '" + (dir / "a.csv").string() +
                                "' '" + (dir / other).string() + "' > /dev/null";
    const int s = std::system(command.c_str());
    return WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  };
  EXPECT_EQ(status("times.csv"), 0);
  EXPECT_EQ(status("wrong.csv"), 1);
  fs::remove_all(dir);
}

// prediction_floor.py on three runs whose Z-fail frames take 2, 2, 4, 4 and 4
// times as long in the second and third as in the first.  From one run to
// the next: along a path (the last frame's ratio) the second run's times
// follow exactly from the first's; across sampled configurations (the median
// of the last 8 ratios) they are off by half on the median frame, and by
// all of it from the second back to the first.  From the mean of the other
// runs: the first run is off by all of it, the others by 1 - 2^-1/2 (the
// ratio to the mean of 1 and 2 or 4 is the square root of 2 or of 4).
TEST(BenchmarkScripts, PredictionFloorScalesTheOtherRunsTimesByTheWindowsRatios) {
  const fs::path dir = test::temp_path("nearcap_prediction_floor");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const double ratio[] = {2, 2, 4, 4, 4};
  std::ofstream first(dir / "first.csv"), again(dir / "again.csv"), third(dir / "third.csv");
  for (std::ofstream* f : {&first, &again, &third})
    *f << "set,configuration,frame,light,rule,end_to_end_ms,predicted_ms\n";
  for (const std::string set : {"p", "s"})
    for (int k = 0; k < 5; ++k) {
      const std::string key = set + ",c" + std::to_string(k) + "," + (set == "p" ? std::to_string(k) : "") + ",0,";
      first << key << "policy,1.0,1.1\n" << key << "zfail,1.0,\n" << key << "zfail#again,1.2,\n";
      for (std::ofstream* f : {&again, &third})
        *f << key << "policy,1.0,0.95\n" << key << "zfail," << ratio[k] << ",\n" << key << "zfail#again,1.2,\n";
    }
  for (std::ofstream* f : {&first, &again, &third}) f->close();
  const auto output = [&](const std::string& runs) {
    const std::string command = "cd '" + (dir).string() + "' && python3 '" + std::string(NEARCAP_SOURCE_DIR) +
                                "/analysis/benchmarks/prediction_floor.py' " + runs + " > out.txt";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return test::slurp(dir / "out.txt");
  };
  std::string out = output("first.csv again.csv");
  std::string p_part = out.substr(0, out.find("s (")), s_part = out.substr(out.find("s ("));
  EXPECT_NE(p_part.find("p (5 frames, window 1):\n  first.csv: the policy's prediction, median error 10.0%; "
                        "Z-fail timed twice in its rounds, median |again/first - 1| 20.0%\n"
                        "  again.csv: the policy's prediction, median error 5.0%;"),
            std::string::npos)
      << out;
  EXPECT_NE(p_part.find("first.csv then again.csv: Z-fail's frame in the other run, median |B/A - 1| 300.0%; "
                        "from the other run's time, median error 0.0% (A to B), 0.0% (B to A)"),
            std::string::npos)
      << out;
  EXPECT_NE(s_part.find("s (5 frames, window 8):"), std::string::npos) << out;
  EXPECT_NE(s_part.find("from the other run's time, median error 50.0% (A to B), 100.0% (B to A)"), std::string::npos)
      << out;
  EXPECT_EQ(out.find("from the mean of the other"), std::string::npos) << out;
  out = output("first.csv again.csv third.csv");
  s_part = out.substr(out.find("s ("));
  EXPECT_NE(s_part.find("first.csv: from the mean of the other 2 runs' times, median error 100.0%\n"
                        "  again.csv: from the mean of the other 2 runs' times, median error 29.3%\n"
                        "  third.csv: from the mean of the other 2 runs' times, median error 29.3%\n"),
            std::string::npos)
      << out;
  fs::remove_all(dir);
}

// orbit_against_build.sh runs the two builds alternately, the order swapped
// from one pair to the next, and prints each pair's ratio and their median:
// stub builds log each call and print a rate (the first 10, 20, 30 /s at its
// 1st, 2nd, 3rd call, the other 10 /s).
TEST(BenchmarkScripts, OrbitAgainstBuildAlternatesTheBuildsAndGivesTheRatiosMedian) {
  const fs::path dir = test::temp_path("nearcap_orbit_against_build");
  fs::remove_all(dir);
  const auto stub = [&](const std::string& name, const std::string& rate) {
    fs::create_directories(dir / name);
    std::ofstream(dir / name / "nearcap")
        << "#!/bin/sh\necho " << name << " >> '" << (dir / "calls.txt").string() << "'\n"
        << "echo 'sweep: 1/40 configurations' >&2\n"
        << "echo \"sweep: 40 configurations in 2.0 s (" << rate << " per second), rows in x\"\n";
    fs::permissions(dir / name / "nearcap", fs::perms::owner_all);
  };
  stub("a", "$((10 * $(grep -c a '" + (dir / "calls.txt").string() + "'))).00");
  stub("b", "10.00");
  const std::string command = "cd '" + std::string(NEARCAP_SOURCE_DIR) + "' && " + test::kHangBound +
                              " analysis/benchmarks/orbit_against_build.sh '" + (dir / "a").string() + "' '" +
                              (dir / "b").string() + "' 3 > '" + (dir / "out.txt").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(test::slurp(dir / "calls.txt"), "a\nb\nb\na\na\nb\n");
  const std::string out = test::slurp(dir / "out.txt");
  EXPECT_NE(out.find("a 10.00 /s  " + (dir / "b").string() + " 10.00 /s  ratio 1.000\n"), std::string::npos) << out;
  EXPECT_NE(out.find("a 20.00 /s  " + (dir / "b").string() + " 10.00 /s  ratio 2.000\n"), std::string::npos) << out;
  EXPECT_NE(out.find("a 30.00 /s  " + (dir / "b").string() + " 10.00 /s  ratio 3.000\n"), std::string::npos) << out;
  EXPECT_NE(out.find("3 pairs: ratio median 2.000, range 1.000-3.000\n"), std::string::npos) << out;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nearcap
