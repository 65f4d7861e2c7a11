// analysis/calibration_file.hpp: `nearcap calibrate`'s CSV written and read
// back exactly, and its bad rows refused with the line and column named.
#include "nearcap/analysis/calibration_file.hpp"

#include <gtest/gtest.h>

#include <string>

#include "nearcap/analysis/device_profile_fit.hpp"
#include "nearcap/error.hpp"

namespace nearcap {
namespace {

using analysis::CalibrationSet;
using analysis::CpuTask;
using analysis::PassKind;

CalibrationSet sample_set() {
  CalibrationSet s;
  s.passes.push_back({"path:near_plane_sweep:42:light0:zfail", PassKind::Sides, 1200, 5320, 0.1, 1315});
  s.passes.push_back({"sample:1:7:zpass", PassKind::Depth, 24012, 19200, 1.0 / 3.0, 0});
  s.passes.push_back({"sample:1:7:light1:zpplus", PassKind::NearCap, 0, 0, 0, 0});
  s.passes.push_back({"sample:1:7:light1:zpass", PassKind::Lit, 3, 1e-300, 123456789.123456789, 2.5});
  s.again.push_back({"sample:1:7:zpass", PassKind::Depth, 24012, 19200, 0.37, 17});
  s.eye_count.push_back({"sample:1:7:light0:atomiczp", 12, 19200, 0.25});
  s.cpu.push_back({"sample:1:7:light0:object1", CpuTask::Silhouette, 960, 0.052});
  s.cpu.push_back({"sample:1:7:light0:object1", CpuTask::ClippedCap, 96, 2.5e-5, 960, 0.1 + 1e-17, 0, 1.0 / 7.0});
  s.cpu.push_back({"sample:1:7:light0", CpuTask::ExactTest, 12000, 7.125, 12000, 6000, 31});
  s.frames.push_back({"sample:1:7:zpass", 0.1 + 0.2});
  s.frames.push_back({"path:near_plane_sweep:42:zfail", 1.93});
  return s;
}

TEST(CalibrationFile, RoundTripsExactly) {
  const CalibrationSet s = sample_set();
  const std::string text = analysis::calibration_csv(s);
  EXPECT_EQ(text.rfind("record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined,in_view\n", 0), 0u)
      << text;
  const CalibrationSet r = analysis::parse_calibration_csv(text, "test.csv");
  ASSERT_EQ(r.passes.size(), s.passes.size());
  ASSERT_EQ(r.again.size(), s.again.size());
  ASSERT_EQ(r.cpu.size(), s.cpu.size());
  for (std::size_t k = 0; k < s.passes.size(); ++k) {
    EXPECT_EQ(r.passes[k].frame, s.passes[k].frame);
    EXPECT_EQ(r.passes[k].kind, s.passes[k].kind);
    EXPECT_EQ(r.passes[k].triangles, s.passes[k].triangles);
    EXPECT_EQ(r.passes[k].fragments, s.passes[k].fragments);
    EXPECT_EQ(r.passes[k].ms, s.passes[k].ms) << "bit for bit";
    EXPECT_EQ(r.passes[k].in_view, s.passes[k].in_view);
  }
  EXPECT_EQ(r.again[0].ms, 0.37);
  EXPECT_EQ(r.again[0].in_view, 17);
  ASSERT_EQ(r.eye_count.size(), 1u);
  EXPECT_EQ(r.eye_count[0].triangles, 12);
  EXPECT_NE(text.find("\npass,sample:1:7:light0:atomiczp,eye_count,12,19200,0.25,,,,,\n"), std::string::npos) << text;
  for (std::size_t k = 0; k < s.cpu.size(); ++k) {
    EXPECT_EQ(r.cpu[k].frame, s.cpu[k].frame);
    EXPECT_EQ(r.cpu[k].task, s.cpu[k].task);
    EXPECT_EQ(r.cpu[k].triangles, s.cpu[k].triangles);
    EXPECT_EQ(r.cpu[k].ms, s.cpu[k].ms);
    EXPECT_EQ(r.cpu[k].reaching, s.cpu[k].reaching);
    EXPECT_EQ(r.cpu[k].tested, s.cpu[k].tested) << "bit for bit";
    EXPECT_EQ(r.cpu[k].straddling, s.cpu[k].straddling);
    EXPECT_EQ(r.cpu[k].examined, s.cpu[k].examined) << "bit for bit";
  }
  ASSERT_EQ(r.frames.size(), s.frames.size());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    EXPECT_EQ(r.frames[k].frame, s.frames[k].frame);
    EXPECT_EQ(r.frames[k].ms, s.frames[k].ms) << "bit for bit";
  }
  EXPECT_NE(text.find("\nframe,sample:1:7:zpass,end_to_end,,,0.30000000000000004,,,,,\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\npass,path:near_plane_sweep:42:light0:zfail,sides,1200,5320,0.1,,,,,1315\n"), std::string::npos)
      << text;
  EXPECT_EQ(analysis::calibration_csv(r), text) << "written again, the same bytes";
}

TEST(CalibrationFile, APassBelongsToTheWholeFrameOfItsConfigurationAndMethod) {
  EXPECT_EQ(analysis::frame_of_pass("sample:1:7:light0:zfail"), "sample:1:7:zfail");
  EXPECT_EQ(analysis::frame_of_pass("path:near_plane_sweep:42:light12:zpplus-clipped-sides"),
            "path:near_plane_sweep:42:zpplus-clipped-sides");
  EXPECT_EQ(analysis::frame_of_pass("sample:1:7:zfail"), "sample:1:7:zfail") << "the depth and lit passes";
  EXPECT_EQ(analysis::frame_of_pass("light3:zpass"), "zpass");
  for (const char* own : {"sample:1:7:lightx:zfail", "sample:1:7:light:zfail", "sample:1:7:light0", "zfail",
                          "sample:1:7:light0:", ":zfail"})
    EXPECT_EQ(analysis::frame_of_pass(own), own) << "not a light frame's pass";
}

TEST(CalibrationFile, NoiseFloorPairsTheSameFrameAndKind) {
  const CalibrationSet s = sample_set();
  const std::vector<double> r = analysis::noise_floor_ratios(s);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_DOUBLE_EQ(r[0], 0.37 / (1.0 / 3.0));
}

// The error kind and message of parsing `rows` after the header.
std::pair<ErrorKind, std::string> refusal(
    const std::string& rows,
    const std::string& header =
        "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined,in_view\n") {
  try {
    analysis::parse_calibration_csv(header + rows, "bad.csv");
  } catch (const Error& e) {
    return {e.kind(), e.what()};
  }
  return {ErrorKind::Io, "accepted"};
}

TEST(CalibrationFile, RefusesBadRowsNamingLineAndColumn) {
  struct Case {
    std::string rows;
    ErrorKind kind;
    std::string says;
  };
  const Case cases[] = {
      {"pass,f,sides,1,2,nan,,,,,\n", ErrorKind::NonFinite, "line 2: ms 'nan' is not finite"},
      {"pass,f,sides,1,2,1e999,,,,,\n", ErrorKind::NonFinite, "ms '1e999' is not finite"},
      {"pass,f,sides,-1,2,3,,,,,\n", ErrorKind::Schema, "line 2: triangles -1 is negative"},
      {"pass,f,sides,1,x,3,,,,,\n", ErrorKind::Parse, "fragments 'x' is not a number"},
      {"pass,f,sides,1,,3,,,,,\n", ErrorKind::Parse, "fragments '' is not a number"},
      {"pass,f,caps,1,2,3,,,,,\n", ErrorKind::Parse, "kind 'caps' is not a pass kind"},
      {"cpu,f,sides,1,,3,,,,,\n", ErrorKind::Parse, "kind 'sides' is not a CPU task"},
      {"cpu,f,silhouette,1,2,3,,,,,\n", ErrorKind::Parse, "a cpu record has no fragments"},
      {"pass,f,sides,1,2,3,,,\n", ErrorKind::Parse, "line 2: 9 fields, not 11"},
      {"pass,f,sides,1,2,3\n", ErrorKind::Parse, "line 2: 6 fields, not 11"},
      {"pass,f,sides,1,2,3,,,,,1,\n", ErrorKind::Parse, "12 fields, not 11"},
      {"timing,f,sides,1,2,3,,,,,\n", ErrorKind::Parse, "record 'timing' is not pass, again, cpu or frame"},
      {"pass,f,sides,1,2,3,,,,,1\n\npass,,sides,1,2,3,,,,,1\n", ErrorKind::Parse, "line 4: an empty frame"},
      // The triangles in view: a number in a pass kind's rows, empty elsewhere.
      {"pass,f,sides,1,2,3,,,,,\n", ErrorKind::Parse, "line 2: in_view '' is not a number"},
      {"again,f,sides,1,2,3,,,,,-4\n", ErrorKind::Schema, "line 2: in_view -4 is negative"},
      {"pass,f,sides,0,0,3,,,,,4\n", ErrorKind::Schema, "line 2: in_view 4 triangles of a pass that submitted none"},
      {"pass,f,eye_count,1,2,3,,,,,4\n", ErrorKind::Schema, "line 2: in_view '4': the eye-count pass has no"},
      {"cpu,f,silhouette,1,,3,,,,,4\n", ErrorKind::Schema, "line 2: in_view '4': a cpu record has no triangles"},
      {"frame,f,end_to_end,,,3,,,,,4\n", ErrorKind::Schema, "line 2: in_view '4': a frame record has no"},
      // The CPU tasks' counts: numbers where the task has them, empty elsewhere.
      {"cpu,f,clipped_cap,1,,3,4,x,6,,\n", ErrorKind::Parse, "line 2: tested 'x' is not a number"},
      {"cpu,f,exact_test,1,,3,4,5,-6,,\n", ErrorKind::Schema, "line 2: straddling -6 is negative"},
      {"cpu,f,exact_test,1,,3,inf,5,6,,\n", ErrorKind::NonFinite, "line 2: reaching 'inf' is not finite"},
      {"cpu,f,clipped_cap,1,,3,,5,6,,\n", ErrorKind::Parse, "line 2: reaching '' is not a number"},
      {"cpu,f,clipped_cap,1,,3,4,5,6,,\n", ErrorKind::Parse, "line 2: examined '' is not a number"},
      {"cpu,f,clipped_cap,1,,3,4,5,6,-2,\n", ErrorKind::Schema, "line 2: examined -2 is negative"},
      {"pass,f,sides,1,2,3,,,,8,1\n", ErrorKind::Schema, "line 2: examined '8': a pass record has no CPU task"},
      {"cpu,f,silhouette,1,,3,4,,,,\n", ErrorKind::Schema, "line 2: reaching '4': a silhouette record has no"},
      {"pass,f,sides,1,2,3,,,7,,1\n", ErrorKind::Schema, "line 2: straddling '7': a pass record has no CPU task"},
      // The whole frame: its time alone.
      {"frame,f,sides,,,3,,,,,\n", ErrorKind::Parse, "line 2: kind 'sides' of a frame record is not end_to_end"},
      {"frame,f,end_to_end,1,,3,,,,,\n", ErrorKind::Schema, "line 2: a frame record has no triangles or fragments"},
      {"frame,f,end_to_end,,,-3,,,,,\n", ErrorKind::Schema, "line 2: ms -3 is negative"},
      {"frame,f,end_to_end,,,3,,,,1,\n", ErrorKind::Schema, "line 2: examined '1': a frame record has no CPU task"},
  };
  for (const Case& c : cases) {
    const auto [kind, message] = refusal(c.rows);
    EXPECT_EQ(kind, c.kind) << c.rows << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << c.rows << message;
    EXPECT_EQ(message.rfind("bad.csv", 0), 0u) << message;
  }
  const auto [kind, message] = refusal("pass,f,sides,1,2,3\n", "frame,kind,ms\n");
  EXPECT_EQ(kind, ErrorKind::Parse);
  EXPECT_NE(message.find("line 1: the header is not"), std::string::npos) << message;
  // A file whose cpu rows carry the triangles alone: refused, saying why.
  const auto [old_kind, old_message] =
      refusal("cpu,f,clipped_cap,96,,0.3\n", "record,frame,kind,triangles,fragments,ms\n");
  EXPECT_EQ(old_kind, ErrorKind::Schema);
  EXPECT_NE(old_message.find("bad.csv line 1: the header is 'record,frame,kind,triangles,fragments,ms': its cpu "
                             "rows lack the counts reaching, tested and straddling"),
            std::string::npos)
      << old_message;
  EXPECT_EQ(old_message.find('\n'), std::string::npos) << old_message;
  // A file whose cpu rows lack the clipped-sides cap's examined faces:
  // refused, saying why.
  const auto [nine_kind, nine_message] =
      refusal("cpu,f,clipped_cap,96,,0.3,960,144,21\n",
              "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling\n");
  EXPECT_EQ(nine_kind, ErrorKind::Schema);
  EXPECT_NE(nine_message.find("bad.csv line 1: the header is 'record,frame,kind,triangles,fragments,ms,reaching,"
                              "tested,straddling': its cpu rows lack the count examined"),
            std::string::npos)
      << nine_message;
  EXPECT_NE(nine_message.find("run nearcap calibrate again"), std::string::npos) << nine_message;
  EXPECT_EQ(nine_message.find('\n'), std::string::npos) << nine_message;
  // A file whose pass rows lack their triangles in view: refused, saying why.
  const auto [ten_kind, ten_message] = refusal(
      "pass,f,sides,1,2,3,,,,\n", "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined\n");
  EXPECT_EQ(ten_kind, ErrorKind::Schema);
  EXPECT_NE(ten_message.find("bad.csv line 1: the header is 'record,frame,kind,triangles,fragments,ms,reaching,"
                             "tested,straddling,examined': its pass rows lack the count in_view"),
            std::string::npos)
      << ten_message;
  EXPECT_NE(ten_message.find("run nearcap calibrate again"), std::string::npos) << ten_message;
  EXPECT_EQ(ten_message.find('\n'), std::string::npos) << ten_message;
  EXPECT_THROW(analysis::parse_calibration_csv("", "empty.csv"), Error);
}

TEST(CalibrationFile, RefusesAFrameNameThatWouldBreakTheCsv) {
  CalibrationSet s;
  s.passes.push_back({"a,b", PassKind::Sides, 1, 2, 3});
  EXPECT_THROW(analysis::calibration_csv(s), Error);
}

}  // namespace
}  // namespace nearcap
