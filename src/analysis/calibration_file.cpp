// nearcap calibrate's observations as CSV (see calibration_file.hpp).
#include "nearcap/analysis/calibration_file.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <utility>

#include "nearcap/error.hpp"

namespace nearcap::analysis {
namespace {

constexpr std::string_view kHeader =
    "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined,in_view";
// The headers of older files: cpu rows with the triangles alone, with the
// counts but not the clipped-sides cap's examined faces, and pass rows
// without their triangles in view.
constexpr std::string_view kTrianglesOnlyHeader = "record,frame,kind,triangles,fragments,ms";
constexpr std::string_view kWithoutExaminedHeader =
    "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling";
constexpr std::string_view kWithoutInViewHeader =
    "record,frame,kind,triangles,fragments,ms,reaching,tested,straddling,examined";
constexpr std::array<std::string_view, 11> kColumns{"record",   "frame",  "kind",       "triangles", "fragments", "ms",
                                                    "reaching", "tested", "straddling", "examined",  "in_view"};
// The CPU tasks' counts: reaching..examined.
constexpr std::size_t kFirstCountColumn = 6, kInViewColumn = 10;

// A frame row's kind: the whole frame, timed end to end.
constexpr std::string_view kEndToEnd = "end_to_end";

// The shortest text that reads back to `v` exactly (std::to_chars).
std::string number(double v, std::string_view what) {
  if (!std::isfinite(v)) throw Error(ErrorKind::NonFinite, "calibration CSV: a non-finite " + std::string(what));
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}

void check_frame(const std::string& frame) {
  if (frame.find_first_of(",\"\r\n") != std::string::npos)
    throw Error(ErrorKind::Usage, "calibration CSV: frame name '" + frame + "' has a comma, quote or line break");
}

std::string pass_line(std::string_view record, const PassObservation& o) {
  check_frame(o.frame);
  return std::string(record) + "," + o.frame + "," + std::string(to_string(o.kind)) + "," +
         number(o.triangles, "triangle count") + "," + number(o.fragments, "fragment count") + "," +
         number(o.ms, "time") + ",,,,," + number(o.in_view, "in-view count") + "\n";
}

}  // namespace

std::optional<PassKind> pass_kind_from_string(std::string_view name) {
  for (std::size_t k = 0; k < kPassKindCount; ++k)
    if (kPassKindNames[k] == name) return static_cast<PassKind>(k);
  return std::nullopt;
}

std::optional<CpuTask> cpu_task_from_string(std::string_view name) {
  for (std::size_t k = 0; k < kCpuTaskNames.size(); ++k)
    if (kCpuTaskNames[k] == name) return static_cast<CpuTask>(k);
  return std::nullopt;
}

std::string calibration_csv_header() { return std::string(kHeader) + "\n"; }

std::string calibration_csv_rows(const CalibrationSet& set) {
  std::string out;
  for (const PassObservation& o : set.passes) out += pass_line("pass", o);
  for (const EyeCountObservation& o : set.eye_count) {
    check_frame(o.frame);
    out += "pass," + o.frame + "," + std::string(kEyeCountPassName) + "," + number(o.triangles, "triangle count") +
           "," + number(o.fragments, "fragment count") + "," + number(o.ms, "time") + ",,,,,\n";
  }
  for (const PassObservation& o : set.again) out += pass_line("again", o);
  for (const CpuObservation& o : set.cpu) {
    check_frame(o.frame);
    out += "cpu," + o.frame + "," + std::string(to_string(o.task)) + "," + number(o.triangles, "triangle count") +
           ",," + number(o.ms, "time");
    if (o.task == CpuTask::Silhouette)
      out += ",,,,,\n";
    else
      out += "," + number(o.reaching, "reaching count") + "," + number(o.tested, "tested count") + "," +
             number(o.straddling, "straddling count") + "," + number(o.examined, "examined count") + ",\n";
  }
  for (const FrameObservation& o : set.frames) {
    check_frame(o.frame);
    out += "frame," + o.frame + "," + std::string(kEndToEnd) + ",,," + number(o.ms, "time") + ",,,,,\n";
  }
  return out;
}

CalibrationSet parse_calibration_csv(std::string_view text, const std::string& source) {
  CalibrationSet set;
  std::size_t line_number = 0, at = 0;
  auto fail = [&](ErrorKind kind, const std::string& what) -> Error {
    return Error(kind, source + " line " + std::to_string(line_number) + ": " + what);
  };
  bool header = false;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!header) {
      if (line == kTrianglesOnlyHeader)
        throw fail(ErrorKind::Schema, "the header is '" + std::string(kTrianglesOnlyHeader) +
                                          "': its cpu rows lack the counts reaching, tested and straddling that the "
                                          "device profile's CPU tasks are priced by (run nearcap calibrate again)");
      if (line == kWithoutExaminedHeader)
        throw fail(ErrorKind::Schema, "the header is '" + std::string(kWithoutExaminedHeader) +
                                          "': its cpu rows lack the count examined (the faces the light-pyramid cull "
                                          "tested) that the clipped-sides cap is priced by (run nearcap calibrate "
                                          "again)");
      if (line == kWithoutInViewHeader)
        throw fail(ErrorKind::Schema, "the header is '" + std::string(kWithoutInViewHeader) +
                                          "': its pass rows lack the count in_view (the set-up triangles meeting "
                                          "the viewport) that the device profile prices each pass by (run nearcap "
                                          "calibrate again)");
      if (line != kHeader)
        throw fail(ErrorKind::Parse, "the header is not '" + std::string(kHeader) +
                                         "' (a calibration CSV of "
                                         "nearcap calibrate)");
      header = true;
      continue;
    }
    if (line.empty()) continue;
    std::array<std::string_view, kColumns.size()> field;
    std::size_t n = 0, from = 0;
    while (true) {
      const std::size_t comma = line.find(',', from);
      if (n < field.size()) field[n] = line.substr(from, comma == std::string_view::npos ? comma : comma - from);
      ++n;
      if (comma == std::string_view::npos) break;
      from = comma + 1;
    }
    if (n != field.size())
      throw fail(ErrorKind::Parse, std::to_string(n) + " fields, not " + std::to_string(field.size()) + " (" +
                                       std::string(kHeader) + ")");
    auto value = [&](std::size_t column) {
      const std::string_view t = field[column];
      const std::string name(kColumns[column]);
      double v = 0;
      const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
      const bool whole = !t.empty() && r.ptr == t.data() + t.size();
      if (whole && (r.ec == std::errc::result_out_of_range || (r.ec == std::errc() && !std::isfinite(v))))
        throw fail(ErrorKind::NonFinite, name + " '" + std::string(t) + "' is not finite");
      if (!whole || r.ec != std::errc())
        throw fail(ErrorKind::Parse, name + " '" + std::string(t) + "' is not a number");
      if (v < 0) throw fail(ErrorKind::Schema, name + " " + std::string(t) + " is negative");
      return v;
    };
    const std::string_view record = field[0];
    const std::string frame(field[1]);
    if (frame.empty()) throw fail(ErrorKind::Parse, "an empty frame");
    // The counts columns: numbers for the clipped-sides cap's and the exact
    // test's cpu rows, empty for the others; in_view: a number for the
    // pass and again rows of the pass kinds, empty for the others.
    auto counts_empty = [&](const std::string& what) {
      for (std::size_t column = kFirstCountColumn; column < kInViewColumn; ++column)
        if (!field[column].empty())
          throw fail(ErrorKind::Schema,
                     std::string(kColumns[column]) + " '" + std::string(field[column]) + "': " + what + " (empty)");
    };
    auto in_view_empty = [&](const std::string& what) {
      if (!field[kInViewColumn].empty())
        throw fail(ErrorKind::Schema, "in_view '" + std::string(field[kInViewColumn]) + "': " + what +
                                          " has no triangles in view (empty)");
    };
    if (record == "pass" && field[2] == kEyeCountPassName) {
      counts_empty("a pass record has no CPU task counts");
      in_view_empty("the eye-count pass");
      set.eye_count.push_back({frame, value(3), value(4), value(5)});
    } else if (record == "pass" || record == "again") {
      const std::optional<PassKind> kind = pass_kind_from_string(field[2]);
      if (!kind) throw fail(ErrorKind::Parse, "kind '" + std::string(field[2]) + "' is not a pass kind");
      counts_empty("a " + std::string(record) + " record has no CPU task counts");
      PassObservation o{frame, *kind, value(3), value(4), value(5), value(kInViewColumn)};
      if (o.in_view > 0 && o.triangles == 0)
        throw fail(ErrorKind::Schema,
                   "in_view " + std::string(field[kInViewColumn]) + " triangles of a pass that submitted none");
      (record == "pass" ? set.passes : set.again).push_back(std::move(o));
    } else if (record == "cpu") {
      const std::optional<CpuTask> task = cpu_task_from_string(field[2]);
      if (!task) throw fail(ErrorKind::Parse, "kind '" + std::string(field[2]) + "' is not a CPU task");
      if (!field[4].empty()) throw fail(ErrorKind::Parse, "a cpu record has no fragments (the column is empty)");
      CpuObservation o{frame, *task, value(3), value(5)};
      in_view_empty("a cpu record");
      if (*task == CpuTask::Silhouette) {
        counts_empty("a silhouette record has no near-plane counts");
      } else {
        o.reaching = value(6);
        o.tested = value(7);
        o.straddling = value(8);
        o.examined = value(9);
      }
      set.cpu.push_back(std::move(o));
    } else if (record == "frame") {
      if (field[2] != kEndToEnd)
        throw fail(ErrorKind::Parse,
                   "kind '" + std::string(field[2]) + "' of a frame record is not " + std::string(kEndToEnd));
      if (!field[3].empty() || !field[4].empty())
        throw fail(ErrorKind::Schema, "a frame record has no triangles or fragments (the columns are empty)");
      counts_empty("a frame record has no CPU task counts");
      in_view_empty("a frame record");
      set.frames.push_back({frame, value(5)});
    } else {
      throw fail(ErrorKind::Parse, "record '" + std::string(record) + "' is not pass, again, cpu or frame");
    }
  }
  if (!header) throw Error(ErrorKind::Parse, source + ": empty (no header line)");
  return set;
}

std::vector<double> noise_floor_ratios(const CalibrationSet& set) {
  std::map<std::pair<std::string, PassKind>, double> first;
  for (const PassObservation& o : set.passes) first[{o.frame, o.kind}] = o.ms;
  std::vector<double> out;
  for (const PassObservation& o : set.again) {
    const auto f = first.find({o.frame, o.kind});
    if (f != first.end() && f->second > 0) out.push_back(o.ms / f->second);
  }
  return out;
}

}  // namespace nearcap::analysis
