// nearcap/analysis/sweep_file.hpp — a sweep's CSV as a file that is
// continued: its sidecar (what made the rows) and the check of every row
// before `nearcap sweep --resume` appends to it.  docs/sweep-files.md has the
// rules for users.
//
// The CSV itself is only rows (sweep.hpp: csv_header, csv_line); what
// determines them lives beside it in CSV.meta.json, the sidecar:
//
//   {"format": "nearcap sweep sidecar", "format_version": 1,
//    "nearcap": "0.1.0", "samples": 60,
//    "options": {"--methods": ["zpass", "zfail"], "--width": "40", ...}}
//
// "options" holds every option that changes a row, each as a list of strings
// (a list of one as that string) in a fixed order (SweepMeta::options);
// "samples" is apart because a resume
// may raise it (configurations are enumerated in a fixed order, paths' frames
// first, so a larger --samples only appends configurations).
//
// A configuration's rows form a group: one row per (light, variant, entry)
// with the light outermost and the entries (methods, then engine policies,
// then "policy") innermost, or one row with method "rejected" when its scene
// does not load.  check_sweep_file reads the CSV as a stream (any size),
// checks every row against the group it must belong to, and says where the
// complete groups end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nearcap::analysis {

// The longest line a reader of sweep CSVs takes (--resume, tune; the
// report's reader has the same bound): a sweep row is under 1 kB, so a longer
// line is not one, and no reader holds more than this of a line in memory.
inline constexpr std::size_t kMaxSweepLineBytes = std::size_t{1} << 20;

// ---- the sidecar -----------------------------------------------------------

struct SweepMeta {
  std::string nearcap_version;  // "0.1.0"
  std::uint64_t samples = 0;
  // Option name ("--width") and its value(s), in the order they are compared.
  std::vector<std::pair<std::string, std::vector<std::string>>> options;
};

// The sidecar key of each camera path's base scene and meshes digest.
inline constexpr const char* kPathSceneDigestKey = "--path (scene and meshes digest)";
// The sidecar key of the digest of the mesh files the sampler reads
// (NEARCAP_DATA_DIR's or the shipped data/meshes).
inline constexpr const char* kSamplerMeshesDigestKey = "--samples (meshes digest)";

// "results.csv" -> "results.csv.meta.json".
std::string sweep_meta_path(const std::string& csv);
// The sidecar's text (JSON, ending in a newline).
std::string sweep_meta_json(const SweepMeta& meta);
// Reads a sidecar's text; `file` names it in errors (Parse: not JSON;
// Schema: not a sweep sidecar, or a field of the wrong type).
SweepMeta parse_sweep_meta(const std::string& text, const std::string& file);
// Why `here` (this command's options) cannot continue the sweep made with
// `resumed`, naming the first option that differs ("--width: 40 here, 48 in
// the sweep being resumed"), or nullopt when it can: every option equal, the
// same nearcap version, and here.samples >= resumed.samples.
std::optional<std::string> resume_mismatch(const SweepMeta& here, const SweepMeta& resumed);

// FNV-1a, 64 bits.
std::uint64_t fnv1a_64(std::string_view bytes);
// fnv1a_64 as 16 hex digits: tells a changed input file (a camera path, the
// switch policy) from the one a sweep was made with.
std::string content_digest(const std::string& bytes);

// ---- the rows --------------------------------------------------------------

// What the rows of configuration k must hold.
struct ExpectedGroup {
  std::string id, source, kind, detail, replay;  // the CSV's columns of every row of the group
  std::size_t lights = 0;                        // of its scene; 0 when the scene text is not even JSON
  // Whether its scene loads: one that does not has one row, "rejected".
  bool loads = true;
  // For a scene that loads and yet has a "rejected" row (an error past the
  // scene's reading): whether computing the configuration again is
  // rejected too.  Unset: such a row is a fault.
  std::function<bool()> rejected_after_loading;
};

// The row layout of every group: the variant names and the entry names
// (methods, engine policies, "policy") in the order sweep_configuration
// writes them.
struct SweepLayout {
  std::vector<std::string> variants, entries;
};

struct SweepFileCheck {
  std::uint64_t groups = 0;          // complete configurations 0 .. groups-1, in order
  std::uint64_t complete_bytes = 0;  // the CSV's size up to the end of the last complete group
  std::uint64_t lines = 0;           // physical lines up to there (the header's included)
  // Non-empty when the file goes on past complete_bytes with the start of the
  // next group only (a write cut off by a kill): what is wrong there, naming
  // its line.  Everything past complete_bytes is that group's.
  std::string cut_tail;
};

// Reads the CSV from the file descriptor `fd` (positioned reads, any size;
// `file` names it in messages) and checks it: the header is csv_header(),
// every row has the header's field count, and the rows are groups 0, 1, ...
// of `expected` (at most `count` of them) in order, each complete.  A fault
// before the last group, or any fault that a cut-off write cannot leave
// (a row ending in a newline that is short, of another configuration, out of
// order, repeated), throws Error(Schema) naming its line.  A last group that
// is only begun, or whose last line has no newline, is reported in cut_tail.
SweepFileCheck check_sweep_file(int fd, const std::string& file, const SweepLayout& layout, std::uint64_t count,
                                const std::function<ExpectedGroup(std::uint64_t)>& expected);

}  // namespace nearcap::analysis
