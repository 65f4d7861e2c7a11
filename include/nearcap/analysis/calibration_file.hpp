// nearcap/analysis/calibration_file.hpp — the observations `nearcap
// calibrate` measures (device_profile.hpp's PassObservation and
// CpuObservation) as a CSV file, and read back; docs/calibration.md
// describes the format for readers in other languages.
//
//   record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined,in_view
//   pass,path:near_plane_sweep:42:light0:zfail,sides,1200,5320,0.184,,,,,1315
//   again,path:near_plane_sweep:42:light0:zpass,sides,1200,5102,0.171,,,,,1290
//   cpu,path:near_plane_sweep:42:light0:object1,silhouette,960,,0.052,,,,,
//   cpu,path:near_plane_sweep:42:light0:object1,clipped_cap,96,,0.31,960,144,21,512,
//   frame,path:near_plane_sweep:42:zfail,end_to_end,,,1.93,,,,,
//
// record   "pass": one pass kind of one frame, timed on its own;
//          "again": the same pass of the same frame drawn a second time,
//          later in the same process (the noise floor: again / pass);
//          "cpu": one CPU task (per occluder, or per light for the exact
//          test), timed on its own;
//          "frame": one method's whole lit frame (every light) drawn again
//          without the per-pass timing, timed end to end (FrameObservation;
//          its passes are the pass rows of the same frame, with or without
//          ":lightK" before the method).
// frame    what was drawn: configuration, light, method or object (no
//          comma, quote or line break).
// kind     a pass kind (kPassKindNames) for pass and again, or eye_count
//          for pass (AtomicZP's eye-count pass, kEyeCountPassName), a CPU
//          task (silhouette, clipped_cap, exact_test) for cpu, end_to_end
//          for frame.
// triangles, fragments, ms: finite, non-negative numbers; fragments empty
//          for cpu, triangles and fragments empty for frame.
// reaching, tested, straddling, examined: the clipped_cap's and
//          exact_test's counts (device_profile.hpp, CpuTaskWork; with
//          `triangles`, one run's), finite and non-negative; empty in every
//          other row.
// in_view: a pass or again row's triangles in view (gl::DrawCounters::
//          in_view: the set-up triangles, the clipped polygons' fan pieces
//          among them, whose bounds meet the viewport; more than
//          `triangles` where clipping splits many), finite and
//          non-negative; empty in the eye-count pass's row and every other
//          row.
// A file of an older header (without in_view, without examined, or
// without any count) is refused (schema): calibrate again.
// Numbers are written in the shortest form that reads back to the same
// double, so a file round-trips exactly.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nearcap/analysis/device_profile.hpp"

namespace nearcap::analysis {

inline constexpr std::array<std::string_view, 3> kCpuTaskNames{"silhouette", "clipped_cap", "exact_test"};
inline std::string_view to_string(CpuTask t) { return kCpuTaskNames[static_cast<std::size_t>(t)]; }
using gl::to_string;  // of a PassKind (pass_kind.hpp)
std::optional<PassKind> pass_kind_from_string(std::string_view name);
std::optional<CpuTask> cpu_task_from_string(std::string_view name);

struct CalibrationSet {
  std::vector<PassObservation> passes;         // "pass" rows: what a profile is fitted on
  std::vector<EyeCountObservation> eye_count;  // "pass" rows of kind eye_count (AtomicZP's eye-count pass)
  std::vector<PassObservation> again;          // "again" rows: the noise floor
  std::vector<CpuObservation> cpu;             // "cpu" rows
  std::vector<FrameObservation> frames;        // "frame" rows
};

std::string calibration_csv_header();  // with the trailing newline
// One line per observation (passes, then again, then cpu), each with its
// trailing newline.  Throws Error(Usage) for a frame with a comma, quote or
// line break, Error(NonFinite) for a non-finite number.
std::string calibration_csv_rows(const CalibrationSet& set);
inline std::string calibration_csv(const CalibrationSet& set) {
  return calibration_csv_header() + calibration_csv_rows(set);
}

// Reads calibration_csv's text; `source` names it in errors.  A wrong
// header, a line without nine fields, an unknown record or kind, or a number
// that is not one is an Error(Parse); a non-finite number an
// Error(NonFinite); a negative one, or a count in a row that has none, an
// Error(Schema): each names the line and the column.  A file with the
// six-column header (cpu rows without the counts) is an Error(Schema)
// saying so: its CPU tasks cannot be priced by the counts.
CalibrationSet parse_calibration_csv(std::string_view text, const std::string& source);

// The ratio again / pass of each "again" row whose frame and kind have a
// "pass" row with a positive time: how far the same pass timed twice in one
// process differs.
std::vector<double> noise_floor_ratios(const CalibrationSet& set);

}  // namespace nearcap::analysis
