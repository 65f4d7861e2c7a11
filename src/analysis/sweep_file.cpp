// A sweep's sidecar and the check of its CSV (see sweep_file.hpp).
//
// The check reads the CSV once, front to back, in fixed-size blocks: a sweep
// of a million configurations is gigabytes, and --resume must continue it
// without holding it in memory.  Every row is parsed (RFC 4180: a quoted
// field may hold commas, quotes and line breaks) and compared with the row
// the options make at its place, so that a row lost, repeated or damaged
// anywhere is named by its line instead of being kept or dropped silently.
#include "nearcap/analysis/sweep_file.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "nearcap/analysis/sweep.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/json_reader.hpp"

namespace nearcap::analysis {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kFormat = "nearcap sweep sidecar";
constexpr int kFormatVersion = 1;

std::string listed(const std::vector<std::string>& values) {
  if (values.empty()) return "(none)";
  std::string out;
  for (const std::string& v : values) out += (out.empty() ? "" : ", ") + v;
  return out;
}

// The CSV's records, one at a time, read in blocks with pread.
class RecordReader {
 public:
  RecordReader(int fd, const std::string& file, std::uint64_t offset) : fd_(fd), file_(file), offset_(offset) {}

  // The next line's fields; `terminated` says whether a newline ended it
  // (false: the file ended inside it).  False at the end of the file.  The
  // sweep writes no line break inside a field, so a newline always ends the
  // record: one inside a quoted field, or a line past kMaxSweepLineBytes (of
  // which no more is kept), makes it damaged().
  bool next(std::vector<std::string>& fields, bool& terminated) {
    fields.assign(1, std::string());
    damage_.clear();
    bool any = false, quoted = false;
    std::size_t bytes = 0;
    for (;;) {
      const int c = get();
      if (c < 0) {
        terminated = false;
        return any;
      }
      any = true;
      if (c == '\n') {
        ++lines_;
        terminated = true;
        if (quoted && damage_.empty()) damage_ = "a quoted field is not closed on its line";
        return true;
      }
      if (++bytes > kMaxSweepLineBytes) {
        if (damage_.empty()) {
          damage_ = "longer than " + std::to_string(kMaxSweepLineBytes >> 20) + " MB (a sweep row is under 1 kB)";
          fields.assign(1, std::string());
        }
        continue;
      }
      std::string& field = fields.back();
      if (quoted) {
        if (c == '"') {
          if (peek() == '"') {
            get();
            ++bytes;
            field += '"';
          } else {
            quoted = false;
          }
        } else {
          field += static_cast<char>(c);
        }
      } else if (c == ',') {
        fields.emplace_back();
      } else if (c == '"' && field.empty()) {
        quoted = true;
      } else {
        field += static_cast<char>(c);
      }
    }
  }
  // Why the last record read is not a row the sweep could have written, or "".
  const std::string& damaged() const { return damage_; }
  std::uint64_t offset() const { return offset_; }  // bytes read
  std::uint64_t lines() const { return lines_; }    // newlines read

 private:
  int get() {
    if (at_ == size_ && !fill()) return -1;
    ++offset_;
    return static_cast<unsigned char>(block_[at_++]);
  }
  int peek() {
    if (at_ == size_ && !fill()) return -1;
    return static_cast<unsigned char>(block_[at_]);
  }
  bool fill() {
    for (;;) {
      const ssize_t n = ::pread(fd_, block_.data(), block_.size(), static_cast<off_t>(offset_));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw Error(ErrorKind::Io, file_ + ": cannot read: " + std::strerror(errno));
      at_ = 0;
      size_ = static_cast<std::size_t>(n);
      return n > 0;
    }
  }

  int fd_;
  const std::string& file_;
  std::string damage_;
  std::uint64_t offset_, lines_ = 0;
  std::vector<char> block_ = std::vector<char>(std::size_t{1} << 20);
  std::size_t at_ = 0, size_ = 0;
};

// Two lists of paths naming the same file names in the same order: one
// written another way (p.json and /home/a/p.json), not another file.
bool same_file_names(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  if (a.empty() || a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (std::filesystem::path(a[k]).filename() != std::filesystem::path(b[k]).filename()) return false;
  return true;
}

}  // namespace

std::string sweep_meta_path(const std::string& csv) { return csv + ".meta.json"; }

std::string sweep_meta_json(const SweepMeta& meta) {
  Json j;
  j["format"] = kFormat;
  j["format_version"] = kFormatVersion;
  j["nearcap"] = meta.nearcap_version;
  j["samples"] = meta.samples;
  Json options = Json::object();
  for (const auto& [name, values] : meta.options) {
    if (values.size() == 1)
      options[name] = values.front();  // a one-value list reads as its value
    else
      options[name] = values;
  }
  j["options"] = options;
  // A file name that is not UTF-8 is stored with U+FFFD for each bad byte
  // (resume_mismatch compares the options as stored).
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

SweepMeta parse_sweep_meta(const std::string& text, const std::string& file) {
  const io::JsonDocument doc = io::JsonDocument::parse(text, file);
  const io::JsonValue j = doc.root();
  // The format's name first: another JSON file is named as not a sidecar.
  if (!j.is_object() || !j.has("format") || !j.at("format").is_string() || j.at("format").string() != kFormat)
    j.fail("not a nearcap sweep sidecar (no \"format\": \"" + std::string(kFormat) + "\")");
  const io::JsonValue version = j.at("format_version");
  if (!version.is_integer() || version.integer() != kFormatVersion)
    version.fail("is not " + std::to_string(kFormatVersion) + " (a sidecar of another format version)");
  SweepMeta meta;
  meta.nearcap_version = j.required<std::string>("nearcap");
  meta.samples = j.required<std::uint64_t>("samples");
  for (const auto& [name, values] : j.at("options").members()) {
    if (values.is_string()) {
      meta.options.emplace_back(name, std::vector<std::string>{values.string()});
      continue;
    }
    if (!values.is_array())
      values.fail("expected a string or an array of strings, found " + std::string(values.type_name()));
    std::vector<std::string> list;
    for (const io::JsonValue& v : values.elements()) list.push_back(v.string());
    meta.options.emplace_back(name, std::move(list));
  }
  return meta;
}

std::optional<std::string> resume_mismatch(const SweepMeta& here_as_given, const SweepMeta& resumed) {
  // These options as the sidecar would store them (names that are not UTF-8
  // with U+FFFD), so that a sweep resumes with the options it was made with.
  const SweepMeta here = parse_sweep_meta(sweep_meta_json(here_as_given), "these options");
  const std::string there = " in the sweep being resumed";
  if (here.nearcap_version != resumed.nearcap_version)
    return "this is nearcap " + here.nearcap_version + ", the sweep being resumed was made by nearcap " +
           resumed.nearcap_version + " (its rows could differ)";
  for (const auto& [name, values] : here.options) {
    const auto it = std::find_if(resumed.options.begin(), resumed.options.end(),
                                 [&name = name](const auto& o) { return o.first == name; });
    // A sidecar of this version may lack the paths' scene and meshes
    // digest or the sampler's meshes digest: nothing to compare, the resume
    // goes on as the other options allow.
    if (it == resumed.options.end() && (name == kPathSceneDigestKey || name == kSamplerMeshesDigestKey)) continue;
    // A sweep without samples has no row the sampler's meshes made.
    if (name == kSamplerMeshesDigestKey && resumed.samples == 0) continue;
    if (it == resumed.options.end()) return name + ": " + listed(values) + " here, not recorded" + there;
    if (it->second != values)
      return name + ": " + listed(values) + " here, " + listed(it->second) + there +
             (name == "--path" && same_file_names(values, it->second)
                  ? " (a path is compared as written, as each row's replay column names it: give it as that sweep "
                    "did, from the folder it ran in)"
                  : "");
  }
  for (const auto& [name, values] : resumed.options) {
    const auto it = std::find_if(here.options.begin(), here.options.end(),
                                 [&name = name](const auto& o) { return o.first == name; });
    if (it == here.options.end()) return name + ": " + listed(values) + there + ", unknown to this nearcap";
  }
  if (here.samples < resumed.samples)
    return "--samples: " + std::to_string(here.samples) + " here, " + std::to_string(resumed.samples) + there +
           " (a resume may extend a sweep, not shorten it)";
  return std::nullopt;
}

std::uint64_t fnv1a_64(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string content_digest(const std::string& bytes) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(fnv1a_64(bytes)));
  return buf;
}

SweepFileCheck check_sweep_file(int fd, const std::string& file, const SweepLayout& layout, std::uint64_t count,
                                const std::function<ExpectedGroup(std::uint64_t)>& expected) {
  const std::string header = csv_header();
  {
    std::string start(header.size(), '\0');
    ssize_t n = 0;
    do n = ::pread(fd, start.data(), start.size(), 0);
    while (n < 0 && errno == EINTR);
    if (n < 0) throw Error(ErrorKind::Io, file + ": cannot read: " + std::strerror(errno));
    if (static_cast<std::size_t>(n) != header.size() || start != header) {
      // The header with CR LF line ends (a file saved on Windows): say so.
      const std::string body = header.substr(0, header.size() - 1);
      if (static_cast<std::size_t>(n) == header.size() && start.compare(0, body.size(), body) == 0 &&
          start.back() == '\r')
        throw Error(ErrorKind::Schema, file +
                                           ": line 1 ends in CR LF; nearcap's sweep files end their lines in LF "
                                           "alone (convert it back, e.g. with dos2unix, to resume it)");
      throw Error(ErrorKind::Schema, file + ": line 1 is not the header of this nearcap's sweep files");
    }
  }
  const std::size_t columns = static_cast<std::size_t>(std::count(header.begin(), header.end(), ',')) + 1;
  // The replay column's index (columns are appended after it).
  const std::string_view before_replay(header.data(), header.find(",replay,"));
  const std::size_t replay_column =
      static_cast<std::size_t>(std::count(before_replay.begin(), before_replay.end(), ',')) + 1;
  const std::size_t per_light = layout.variants.size() * layout.entries.size();
  RecordReader reader(fd, file, header.size());
  SweepFileCheck check;
  check.complete_bytes = header.size();
  check.lines = 1;

  ExpectedGroup group;
  std::size_t seen = 0, size = 0;  // rows of the current group read, and its row count
  std::string previous_id;         // of the last complete group
  std::vector<std::string> row;
  bool terminated = false;
  for (;;) {
    const std::uint64_t line = 1 + reader.lines() + 1;
    if (!reader.next(row, terminated)) break;
    const auto fault = [&](const std::string& what) {
      return Error(ErrorKind::Schema, file + ": line " + std::to_string(line) + ": " + what +
                                          " (the file is damaged; --repair mends only a cut-off last configuration)");
    };
    if (!terminated) {
      check.cut_tail = "line " + std::to_string(line) + " has no newline at its end (a write cut off)";
      break;
    }
    if (!reader.damaged().empty()) throw fault(reader.damaged());
    if (row.size() != columns)
      throw fault(std::to_string(row.size()) + " field(s) where the header has " + std::to_string(columns));
    const std::string &id = row[0], &light = row[4], &method = row[5], &variant = row[6];
    if (seen == 0) {
      if (check.groups >= count)
        throw fault("configuration '" + id + "' is past the " + std::to_string(count) +
                    " configurations these options make");
      group = expected(check.groups);
      if (id != group.id)
        throw fault("configuration '" + id + "' where configuration " + std::to_string(check.groups) + " ('" +
                    group.id + "') belongs" + (id == previous_id ? " (a configuration repeated)" : ""));
      if (method == "rejected") {
        if (group.loads && !(group.rejected_after_loading && group.rejected_after_loading()))
          throw fault("configuration '" + id + "' is 'rejected' where its scene loads and its rows are made");
        size = 1;
      } else if (group.lights == 0 || !group.loads) {
        throw fault("configuration '" + id + "' has method " + method + " where its scene can only be rejected");
      } else {
        size = group.lights * per_light;
      }
    }
    if (id != group.id)
      throw fault("configuration '" + id + "' inside the rows of configuration '" + group.id + "' (row " +
                  std::to_string(seen + 1) + " of " + std::to_string(size) + " missing)");
    if (row[1] != group.source || row[2] != group.kind || row[3] != group.detail || row[replay_column] != group.replay)
      throw fault("configuration '" + id +
                  "' has other source, kind, detail or replay columns than these options make");
    if (size == 1 && method == "rejected") {
      if (seen != 0) throw fault("a second 'rejected' row of configuration '" + id + "'");
    } else {
      const std::size_t l = seen / per_light;
      const std::string& want_variant = layout.variants[seen / layout.entries.size() % layout.variants.size()];
      const std::string& want_method = layout.entries[seen % layout.entries.size()];
      if (light != std::to_string(l) || method != want_method || variant != want_variant)
        throw fault("light " + light + ", method " + method + ", variant " + variant + " of configuration '" + id +
                    "' where light " + std::to_string(l) + ", method " + want_method + ", variant " + want_variant +
                    " belongs (row " + std::to_string(seen + 1) + " of " + std::to_string(size) + ")");
    }
    if (++seen == size) {
      ++check.groups;
      check.complete_bytes = reader.offset();
      check.lines = 1 + reader.lines();
      previous_id = group.id;
      seen = 0;
    }
  }
  if (check.cut_tail.empty() && seen != 0)
    check.cut_tail = "configuration '" + group.id + "' ends after " + std::to_string(seen) + " of its " +
                     std::to_string(size) + " rows at line " + std::to_string(1 + reader.lines()) +
                     " (a write cut off)";
  return check;
}

}  // namespace nearcap::analysis
