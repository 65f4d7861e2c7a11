// nearcap sweep: camera paths and hard-case samples through the exact
// reference and the float methods, one CSV row per (configuration, light,
// method).  nearcap sample: one hard-case configuration as a scene file.
//
// Configurations are enumerated in a fixed order (each --path's frames, then
// sampler indices 0..N-1) and run a few at a time on all cores; each
// configuration's rows (its group) are appended to the CSV in one write(), in
// order.  The rules of the file (docs/sweep-files.md):
//   - One writer.  The process that writes the CSV (rank 0 under MPI) holds
//     an exclusive flock on it for the whole sweep; a second sweep on the same
//     file is refused.  A new CSV is made under a temporary name, locked, and
//     linked to its name (link fails when the name exists), so a new sweep and
//     a resume never share a file either.  The kernel drops the lock when the
//     process ends, killed or not.
//   - The CSV describes itself through its sidecar, CSV.meta.json
//     (analysis/sweep_file.hpp): the options that determine the rows, the
//     nearcap version and --samples.  --resume refuses other options, naming
//     the first that differs; only --samples may be larger (the sweep goes on
//     past its old end).  A CSV without a sidecar is not resumed.
//   - --resume reads the whole CSV as a stream and checks every row against
//     the group it belongs to, so that a damaged row anywhere is an error
//     naming its line.  A kill between two writes leaves whole groups, and the
//     resume continues after them with no flag.  A kill inside a write leaves
//     the start of one group (perhaps a last line without its newline): that is
//     an error which names --repair, and --repair cuts the file back to the
//     last whole group, says so on stderr, and runs that configuration again.
// One file of over 600 lines on purpose: the lock, the create-and-link, the
// resume check and the ordered writer below are these rules' code and share
// the configurations' fixed order, so they are read against the rules here.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <tuple>

#include "cli_commands.hpp"
#include "command_output.hpp"
#include "heap_settings.hpp"
#include "mpi_world.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/sweep.hpp"
#include "nearcap/analysis/sweep_file.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/scene_file.hpp"
#include "subcommand.hpp"

namespace nearcap::cli {
namespace {

// One word for a POSIX shell: as it is when it holds only characters no shell
// treats specially, else in single quotes (a quote inside as '\'').  Pasting
// a replay command runs nearcap with exactly these arguments.
std::string shell_word(const std::string& word) {
  const bool plain = !word.empty() && word.find_first_not_of(
                                          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                          "0123456789_@%+=:,./-") == std::string::npos;
  if (plain) return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string sample_replay(const SamplerOptions& o, std::uint64_t index) {
  std::ostringstream s;
  s << "nearcap sample --seed " << o.seed << " --index " << index << " --kinds " << shell_word(o.kinds) << " --width "
    << o.width << " --height " << o.height << (o.allow_bunny ? " --allow-bunny" : "") << " --out c.json";
  return s.str();
}

// ---- nearcap sample --------------------------------------------------------

struct SampleOptions {
  SamplerOptions sampler;
  std::uint64_t index = 0;
  std::string out;
};

void run_sample(const SamplerOptions& o, std::uint64_t index, const std::string& out) {
  const analysis::SamplerSpec spec = sampler_spec(o);
  check_sampler_meshes(spec);
  if (!out.empty()) refuse_replacing_inputs(out, sampler_inputs(spec), "--out");
  const analysis::HardCase c = analysis::HardCaseSampler(spec).sample(index);
  const std::string json = c.scene_json + "\n";
  if (out.empty())
    std::cout << json;
  else
    io::write_output_files({{out, json}});
}

// ---- nearcap sweep ---------------------------------------------------------

struct SweepCommandOptions {
  std::vector<std::string> paths;
  std::uint64_t samples = 0;
  SamplerOptions sampler;
  int width = 0, height = 0;  // 0: each path's own viewport, the sampler's 48 x 36
  std::string methods = "all";
  std::string policies = "none";
  std::string policy_file = shipped_data_dir() + "/policy.json";
  bool policy_given = false;  // --policy on the command line
  EmulationOptions emulation;
  std::vector<std::string> variants;
  std::string out;
  bool resume = false, repair = false;
  double max_memory_gb = 0;
};

// A sweep configuration's memory beyond the fixed part, per pixel of its
// frame: the reference, every method's frame and the crack distances, with
// the default methods (measured: a peak of 195 MB for the room path at
// 1024x768 on 2 cores, two configurations computed at once).  Each core
// computes one configuration at a time.
constexpr double kSweepBytesPerPixel = 120;

// The configurations in their fixed order, made on demand.
class Configurations {
 public:
  // `meshes`: the sweep's, so that reading a path's base scene reads its meshes for the frames.
  Configurations(const SweepCommandOptions& o, MeshCache* meshes) : options_(o) {
    for (const std::string& file : o.paths) {
      analysis::CameraPath path = load_camera_path_file(file, meshes);
      if (o.width > 0) path.width = o.width;
      if (o.height > 0) path.height = o.height;
      paths_.push_back(std::move(path));
    }
    analysis::SamplerSpec spec = sampler_spec(o.sampler);
    if (o.width > 0) spec.width = o.width;
    if (o.height > 0) spec.height = o.height;
    if (o.samples > 0) check_sampler_meshes(spec);
    sampler_options_ = o.sampler;
    sampler_options_.width = spec.width;
    sampler_options_.height = spec.height;
    sampler_ = std::make_unique<analysis::HardCaseSampler>(spec);
    for (const analysis::CameraPath& p : paths_) count_ += static_cast<std::uint64_t>(p.frames);
    count_ += o.samples;
  }
  std::uint64_t count() const { return count_; }
  // The largest frame of the sweep: where it comes from, its width and height.
  std::tuple<std::string, int, int> largest_frame() const {
    std::tuple<std::string, int, int> largest{"", 0, 0};
    const auto pixels = [](int w, int h) { return static_cast<double>(w) * h; };
    for (const analysis::CameraPath& p : paths_)
      if (pixels(p.width, p.height) > pixels(std::get<1>(largest), std::get<2>(largest)))
        largest = {p.source, p.width, p.height};
    if (options_.samples > 0 &&
        pixels(sampler_options_.width, sampler_options_.height) > pixels(std::get<1>(largest), std::get<2>(largest)))
      largest = {"the sampled configurations", sampler_options_.width, sampler_options_.height};
    return largest;
  }

  analysis::SweepConfiguration at(std::uint64_t k) const {
    for (const analysis::CameraPath& p : paths_) {
      if (k < static_cast<std::uint64_t>(p.frames)) {
        const int f = static_cast<int>(k);
        analysis::SweepConfiguration c;
        const std::string name = std::filesystem::path(p.source).stem().string();
        c.id = "path:" + name + ":" + std::to_string(f);
        c.source = p.source;
        c.kind = name;
        c.detail = "frame " + std::to_string(f) + " of " + std::to_string(p.frames);
        try {
          c.scene_json = analysis::path_frame_json(p, f);
        } catch (const Error& e) {
          c.scene_error = e;  // a rejected row, as for a scene that does not load
        }
        c.replay = "nearcap frame " + shell_word(p.source) + " --frame " + std::to_string(f) + " --width " +
                   std::to_string(p.width) + " --height " + std::to_string(p.height) + " --out c.json";
        return c;
      }
      k -= static_cast<std::uint64_t>(p.frames);
    }
    const analysis::HardCase h = sampler_->sample(k);
    analysis::SweepConfiguration c;
    c.id = "sample:" + std::to_string(h.seed) + ":" + std::to_string(h.index);
    c.source = "sampler";
    c.kind = std::string(analysis::to_string(h.kind));
    c.detail = h.detail;
    c.scene_json = h.scene_json;
    c.replay = sample_replay(sampler_options_, h.index);
    return c;
  }

 private:
  const SweepCommandOptions& options_;
  std::vector<analysis::CameraPath> paths_;
  std::unique_ptr<analysis::HardCaseSampler> sampler_;
  SamplerOptions sampler_options_;
  std::uint64_t count_ = 0;
};

// The rows of one configuration as CSV text; a configuration whose scene is
// rejected gets one row with method "rejected" and the error as its fallback.
std::string configuration_csv(const analysis::SweepConfiguration& c, const analysis::SweepOptions& options) {
  std::string text;
  try {
    for (const analysis::SweepRow& r : analysis::sweep_configuration(c, options)) text += analysis::csv_line(r);
  } catch (const Error& e) {
    analysis::SweepRow r;
    r.configuration = c.id;
    r.source = c.source;
    r.kind = c.kind;
    r.detail = c.detail;
    r.replay = c.replay;
    r.method = "rejected";
    r.fallback = std::string(to_string(e.kind())) + ": " + e.what();
    text += analysis::csv_line(r);
  }
  return text;
}

// What the rows of a configuration hold (analysis/sweep_file.hpp): its
// columns, its scene's light count (one group of rows per light), and
// whether the scene loads, read as the sweep reads it.
analysis::ExpectedGroup expected_group(const Configurations& configurations, std::uint64_t k,
                                       const analysis::SweepOptions& options) {
  const analysis::SweepConfiguration c = configurations.at(k);
  analysis::ExpectedGroup g;
  g.id = c.id;
  g.source = c.source;
  g.kind = c.kind;
  g.detail = c.detail;
  g.replay = c.replay;
  const nlohmann::json scene = nlohmann::json::parse(c.scene_json, nullptr, false);
  if (scene.is_object() && scene.contains("lights") && scene["lights"].is_array()) g.lights = scene["lights"].size();
  try {
    (void)parse_scene(c.scene_json, c.id, ".", options.meshes);
  } catch (const Error&) {
    g.loads = false;
  }
  g.rejected_after_loading = [&configurations, k, &options] {
    try {
      (void)analysis::sweep_configuration(configurations.at(k), options);  // what configuration_csv rejects
      return false;
    } catch (const Error&) {
      return true;
    }
  };
  return g;
}

[[noreturn]] void refuse_special(const std::string& file, mode_t mode) {
  throw Error(ErrorKind::Io,
              file + ": " + io::file_kind(mode) + ", not a regular file (--out names the sweep's CSV file)");
}

// Takes the writer's lock on the CSV, or says who holds it.
void lock_csv(int fd, const std::string& file) {
  while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EINTR) continue;
    const int e = errno;
    ::close(fd);
    if (e == EWOULDBLOCK)
      throw Error(ErrorKind::Io, file + ": another nearcap sweep is writing it (it holds the file's lock)");
    throw Error(ErrorKind::Io, file + ": cannot lock it (" + std::strerror(e) +
                                   "): a sweep writes its CSV only where no other sweep can at the same time; put "
                                   "--out on a filesystem with flock (docs/sweep-files.md)");
  }
}

// The existing CSV opened for reading and writing, or -1 when there is none.
int open_existing(const std::string& file) {
  const int fd = ::open(file.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return -1;
    throw Error(ErrorKind::Io, file + ": cannot open it: " + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    refuse_special(file, st.st_mode);
  }
  return fd;
}

void write_all(int fd, const std::string& bytes, const std::string& file) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error(ErrorKind::Io, file + ": write failed: " + std::strerror(errno));
    written += static_cast<std::size_t>(n);
  }
}

// A new sweep writes its sidecar, CSV.meta.json: a file of that name that is
// not a sweep's sidecar (a policy or a camera path the sweep reads, say) is
// refused, never replaced; an earlier sweep's sidecar, left behind by a CSV
// since removed, is replaced.
void refuse_replacing_non_sidecar(const std::string& file) {
  const std::string meta_file = analysis::sweep_meta_path(file);
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(meta_file, ec))) return;
  try {
    (void)analysis::parse_sweep_meta(io::read_input_file(meta_file, "sweep sidecar"), meta_file);
  } catch (const Error& e) {
    throw Error(ErrorKind::Usage, file + ": its sidecar's name " + meta_file +
                                      " is taken by a file that is not a sweep's sidecar (" + e.what() +
                                      "); move that file, or give another --out");
  }
}

// A new CSV (its header) and its sidecar, the CSV locked by this process, or
// -1 when `file` exists.  The header is written to a temporary name, locked
// and then linked to `file`: link fails when the name exists, so no other
// sweep can open the new file before it is locked.
int create_csv(const std::string& file, const analysis::SweepMeta& meta) {
  refuse_replacing_non_sidecar(file);
  const std::filesystem::path parent = std::filesystem::path(file).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  // A name no file has: one left behind by a process killed before it
  // linked it (whose number this one may have, in a container) is skipped.
  std::string temporary;
  int fd = -1;
  for (int k = 0; fd < 0; ++k) {
    temporary = file + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(k);
    fd = ::open(temporary.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && (errno != EEXIST || k == 99))
      throw Error(ErrorKind::Io, file + ": cannot create it (as " + temporary + "): " + std::strerror(errno));
  }
  try {
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
      throw Error(ErrorKind::Io, file + ": cannot lock it: " + std::strerror(errno));
    write_all(fd, analysis::csv_header(), file);
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  if (::link(temporary.c_str(), file.c_str()) != 0) {
    const int e = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    if (e == EEXIST) return -1;
    throw Error(ErrorKind::Io, file + ": cannot create it: " + std::strerror(e));
  }
  ::unlink(temporary.c_str());
  try {
    io::write_output_files({{analysis::sweep_meta_path(file), analysis::sweep_meta_json(meta)}});
  } catch (...) {
    ::unlink(file.c_str());  // still ours: locked since before it had its name
    ::close(fd);
    throw;
  }
  return fd;
}

// Whether the CSV behind `fd` is this nearcap's header and nothing else.
bool holds_only_the_header(int fd, const std::string& file) {
  const std::string header = analysis::csv_header();
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw Error(ErrorKind::Io, file + ": cannot inspect it: " + std::strerror(errno));
  if (static_cast<std::uint64_t>(st.st_size) != header.size()) return false;
  std::string start(header.size(), '\0');
  ssize_t n = 0;
  do n = ::pread(fd, start.data(), start.size(), 0);
  while (n < 0 && errno == EINTR);
  return n == static_cast<ssize_t>(header.size()) && start == header;
}

// --resume: checks the locked CSV against its sidecar and these options, and
// every row (analysis/sweep_file.hpp); returns how many configurations it
// holds whole.  With `repair`, the start of a configuration cut off mid-write
// is removed (and said so); without, it is an error naming --repair.
std::uint64_t resume_point(int fd, const std::string& file, const Configurations& configurations,
                           const analysis::SweepLayout& layout, const analysis::SweepOptions& options,
                           const analysis::SweepMeta& here, bool repair) {
  const std::string meta_file = analysis::sweep_meta_path(file);
  std::error_code ec;
  if (!std::filesystem::exists(meta_file, ec) && holds_only_the_header(fd, file)) {
    // A sweep stopped between making its CSV and writing the sidecar: no
    // row to mix, so these options start it.
    io::write_output_files({{meta_file, analysis::sweep_meta_json(here)}});
    return 0;
  }
  if (!std::filesystem::exists(meta_file, ec))
    throw Error(ErrorKind::Schema, file + ": has no sidecar " + meta_file +
                                       " (what made its rows is unknown: an older nearcap, or not nearcap sweep); "
                                       "it cannot be resumed: start a new sweep with another --out");
  const analysis::SweepMeta resumed =
      analysis::parse_sweep_meta(io::read_input_file(meta_file, "sweep sidecar"), meta_file);
  if (const auto why = analysis::resume_mismatch(here, resumed))
    throw Error(ErrorKind::Usage, file + ": cannot resume it with these options: " + *why);
  const analysis::SweepFileCheck check =
      analysis::check_sweep_file(fd, file, layout, configurations.count(),
                                 [&](std::uint64_t k) { return expected_group(configurations, k, options); });
  if (!check.cut_tail.empty()) {
    if (!repair)
      throw Error(ErrorKind::Schema, file + ": " + check.cut_tail + "; give --resume --repair to remove line " +
                                         std::to_string(check.lines + 1) +
                                         " onwards (the configuration being written) and run it again");
    if (::ftruncate(fd, static_cast<off_t>(check.complete_bytes)) != 0)
      throw Error(ErrorKind::Io,
                  file + ": cannot cut it back to line " + std::to_string(check.lines) + ": " + std::strerror(errno));
    std::fprintf(stderr, "sweep: %s: %s; removed line %llu onwards (--repair): configuration %llu runs again\n",
                 file.c_str(), check.cut_tail.c_str(), static_cast<unsigned long long>(check.lines + 1),
                 static_cast<unsigned long long>(check.groups));
  }
  if (here.samples != resumed.samples)
    io::write_output_files({{meta_file, analysis::sweep_meta_json(here)}});  // extended: more samples
  return check.groups;
}

std::string duration(double seconds) {
  char buf[32];
  const long s = static_cast<long>(seconds + 0.5);
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, s / 60 % 60);
  else
    std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  return buf;
}

// Writes the rows of consecutive configurations as they become ready, in
// configuration order, and reports progress.
class OrderedWriter {
 public:
  // `fd`: the CSV, locked; the writer closes it (which drops the lock).
  OrderedWriter(int fd, const std::string& file, std::uint64_t first, std::uint64_t total, std::size_t methods)
      : file_(file), fd_(fd), first_(first), next_(first), total_(total), last_report_(first) {
    if (::lseek(fd_, 0, SEEK_END) < 0) throw Error(ErrorKind::Io, file + ": cannot seek to its end");
    std::fprintf(stderr, "sweep: %llu configurations (%llu already in %s), %zu method(s)\n",
                 static_cast<unsigned long long>(total), static_cast<unsigned long long>(first), file.c_str(), methods);
  }
  ~OrderedWriter() { ::close(fd_); }
  OrderedWriter(const OrderedWriter&) = delete;
  OrderedWriter& operator=(const OrderedWriter&) = delete;

  void add(std::uint64_t index, std::string rows) {
    ready_[index] = std::move(rows);
    const std::uint64_t before = next_;
    for (auto it = ready_.find(next_); it != ready_.end(); it = ready_.find(next_)) {
      write_group(it->second);
      ready_.erase(it);
      ++next_;
    }
    if (next_ != before) progress();
  }
  bool complete() const { return next_ == total_; }
  void finish() const {
    const double seconds = elapsed();
    if (first_ == total_) {  // a --resume of a finished sweep
      std::printf("sweep: nothing to run: all %llu configurations are already in %s\n",
                  static_cast<unsigned long long>(total_), file_.c_str());
      return;
    }
    if (terminal_) std::fprintf(stderr, "\n");
    std::printf("sweep: %llu configurations in %.1f s (%.2f per second), rows in %s\n",
                static_cast<unsigned long long>(total_ - first_), seconds,
                static_cast<double>(total_ - first_) / std::max(seconds, 1e-9), file_.c_str());
  }

 private:
  // One configuration's rows, whole or not at all: a failed write (a full
  // disk) cuts the file back to where they began, so that the CSV ends with
  // a whole configuration and --resume continues it.
  void write_group(const std::string& rows) {
    const off_t start = ::lseek(fd_, 0, SEEK_CUR);
    try {
      write_all(fd_, rows, file_);
    } catch (const Error& e) {
      if (start >= 0 && ::ftruncate(fd_, start) == 0 && ::lseek(fd_, start, SEEK_SET) == start)
        throw Error(e.kind(), std::string(e.what()) + " (the configuration being written was removed: --resume " +
                                  "continues the sweep)");
      throw Error(e.kind(), std::string(e.what()) + " (the last configuration may be cut off: --resume --repair " +
                                "runs it again)");
    }
  }

  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  void progress() {
    const double rate = static_cast<double>(next_ - first_) / std::max(elapsed(), 1e-9);
    const double eta = static_cast<double>(total_ - next_) / std::max(rate, 1e-9);
    if (terminal_) {
      const int bar = static_cast<int>(30.0 * static_cast<double>(next_) / static_cast<double>(total_));
      std::fprintf(stderr, "\r[%-30s] %llu/%llu  %.1f/s  ETA %s   ", std::string(bar, '#').c_str(),
                   static_cast<unsigned long long>(next_), static_cast<unsigned long long>(total_), rate,
                   duration(eta).c_str());
    } else if (next_ == total_ || (next_ - last_report_) * 10 >= total_) {
      std::fprintf(stderr, "sweep: %llu/%llu configurations, %.1f/s, ETA %s\n", static_cast<unsigned long long>(next_),
                   static_cast<unsigned long long>(total_), rate, duration(eta).c_str());
      last_report_ = next_;
    }
  }

  std::string file_;
  int fd_ = -1;
  std::uint64_t first_, next_, total_, last_report_;
  std::map<std::uint64_t, std::string> ready_;
  bool terminal_ = ::isatty(2) != 0;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

// Under MPI (mpi_world.hpp) rank r runs configurations first + r, first + r +
// size, ... (interleaved, so that each rank gets easy and hard frames of a
// path alike) and sends each one's rows to rank 0, which writes every
// configuration's rows in order.  One process is the world of size 1.
// --policies: engine rules by name, and "policy" (the switch policy); "all"
// is every engine rule and the policy.
std::vector<analysis::EnginePolicy> policies_from(const std::string& names, bool& switch_policy) {
  switch_policy = false;
  if (names == "none") return {};
  if (names == "all") {
    switch_policy = true;
    return {analysis::kAllEnginePolicies.begin(), analysis::kAllEnginePolicies.end()};
  }
  std::vector<analysis::EnginePolicy> out;
  for (const std::string& name : comma_separated(names)) {
    refuse_list_word("--policies", name, {"all", "none"});
    const auto p = analysis::engine_policy_from_string(name);
    if ((name == "policy" && switch_policy) || (p && std::find(out.begin(), out.end(), *p) != out.end()))
      throw Error(ErrorKind::Usage, "--policies names " + name + " twice");
    if (name == "policy") {
      switch_policy = true;
    } else if (!p) {
      throw Error(ErrorKind::Usage, "--policies '" + name + "' is not one of " +
                                        names_joined<analysis::EnginePolicy>() + ", policy (or all, or none)");
    } else {
      out.push_back(*p);
    }
  }
  return out;
}

// The digest of what a camera path's frames are made of besides the path
// file: its base scene's text and every mesh file the scene names.  `meshes`:
// the sweep's cache, which already holds the path's meshes (the bunny's
// reading and validation is most of a short sweep's start).
std::string path_scene_digest(const std::string& path_file, MeshCache* meshes) {
  const analysis::CameraPath path = load_camera_path_file(path_file, meshes);
  const std::string scene_text = io::read_input_file(path.scene_file, "scene file");
  std::string content = scene_text;
  const nlohmann::json scene = nlohmann::json::parse(with_absolute_mesh_paths(scene_text, path.scene_file));
  if (scene.contains("objects") && scene["objects"].is_array())
    for (const nlohmann::json& o : scene["objects"])
      if (o.is_object() && o.contains("mesh") && o["mesh"].is_string()) {
        // The bytes alone: the same files in another folder make the same rows.
        content += '\0' + io::read_input_file(o["mesh"].get<std::string>(), "mesh file");
      }
  return analysis::content_digest(content);
}

// The digest of the mesh files the sampler may read: their bytes, or a mark
// for one that cannot be read (a sweep of paths alone needs none).
std::string sampler_meshes_digest(const SamplerOptions& sampler) {
  std::string content;
  for (const std::string& file : analysis::sampler_mesh_files(sampler_spec(sampler))) {
    try {
      content += io::read_input_file(file, "mesh file");
    } catch (const Error&) {
      content += "(unreadable)";
    }
    content += '\0';
  }
  return analysis::content_digest(content);
}

// The options that determine the rows, for the sidecar (analysis/sweep_file.hpp).
analysis::SweepMeta sweep_meta(const SweepCommandOptions& o, const analysis::SweepOptions& options,
                               const analysis::SweepLayout& layout, MeshCache* meshes) {
  analysis::SweepMeta meta;
  meta.nearcap_version = NEARCAP_VERSION;
  meta.samples = o.samples;
  const auto one = [](const std::string& v) { return std::vector<std::string>{v}; };
  std::vector<std::string> digests, scene_digests;
  for (const std::string& p : o.paths) {
    digests.push_back(analysis::content_digest(io::read_input_file(p, "camera path file")));
    scene_digests.push_back(path_scene_digest(p, meshes));
  }
  meta.options = {
      {"--path", o.paths},
      {"--path (content digest)", digests},
      {analysis::kPathSceneDigestKey, scene_digests},
      {"--seed", one(std::to_string(o.sampler.seed))},
      {"--kinds", one(o.sampler.kinds)},
      {"--allow-bunny", one(o.sampler.allow_bunny ? "yes" : "no")},
      // After --allow-bunny, which changes it: a resume names the option first.
      {analysis::kSamplerMeshesDigestKey, one(sampler_meshes_digest(o.sampler))},
      {"--width", one(o.width > 0 ? std::to_string(o.width) : "default")},
      {"--height", one(o.height > 0 ? std::to_string(o.height) : "default")},
      {"--methods",
       {layout.entries.begin(), layout.entries.begin() + static_cast<std::ptrdiff_t>(options.methods.size())}},
      {"--policies",
       {layout.entries.begin() + static_cast<std::ptrdiff_t>(options.methods.size()), layout.entries.end()}},
      {"--policy (content digest)",
       one(options.switch_policy ? analysis::content_digest(io::read_input_file(o.policy_file, "policy file"))
                                 : "unused")}};
  char exact[40];
  for (auto [name, value] : emulation_option_values(o.emulation)) {
    if (name == "guard-band")
      std::snprintf(exact, sizeof exact, "%.9g", static_cast<double>(o.emulation.settings.raster.guard_band));
    if (name == "l-near-scale")
      std::snprintf(exact, sizeof exact, "%.17g", o.emulation.settings.light_frustum.near_scale);
    if (name == "guard-band" || name == "l-near-scale") value = exact;
    meta.options.push_back({"--" + name, one(value)});
  }
  meta.options.push_back({"--variant", {layout.variants.begin() + 1, layout.variants.end()}});
  return meta;
}

void run_sweep(const SweepCommandOptions& o) {
  keep_freed_memory();  // a sweep's frames allocate and free the same large buffers over and over
  if (o.paths.empty() && o.samples == 0)
    throw Error(ErrorKind::Usage, "nothing to sweep: give --path FILE (repeatable) and/or --samples N");
  if (o.repair && !o.resume) throw Error(ErrorKind::Usage, "--repair mends a sweep being resumed: give --resume too");
  check_camera_path_names(o.paths);
  refuse_unread_sampler_options(o.sampler, o.samples);
  analysis::SweepOptions options;
  options.methods = methods_from(o.methods, "--methods");
  for (std::size_t k = 0; k < options.methods.size(); ++k)
    if (std::find(options.methods.begin(), options.methods.begin() + static_cast<std::ptrdiff_t>(k),
                  options.methods[k]) != options.methods.begin() + static_cast<std::ptrdiff_t>(k))
      throw Error(ErrorKind::Usage, "--methods names " + std::string(gl::to_string(options.methods[k])) + " twice");
  bool switch_policy = false;
  options.policies = policies_from(o.policies, switch_policy);
  refuse_unread_policy(o.policy_given, switch_policy, "--policies policy (or all)");
  if (switch_policy) options.switch_policy = analysis::load_policy(o.policy_file);
  // The options' own choices, then each --variant over them.
  options.variants = {{variant_label(o.emulation), settings_from(o.emulation)}};
  std::set<std::string> names{options.variants.front().name};
  for (const std::string& spec : o.variants) {
    const EmulationOptions v = with_variant(o.emulation, spec);
    const std::string name = variant_label(v);
    if (!names.insert(name).second)
      throw Error(ErrorKind::Usage, "--variant '" + spec + "' repeats the variant " + name);
    options.variants.push_back({name, settings_from(v)});
  }
  // The rows of each light, in sweep_configuration's order.
  analysis::SweepLayout layout;
  for (const analysis::SweepVariant& v : options.variants) layout.variants.push_back(v.name);
  for (gl::ShadowMethod m : options.methods) layout.entries.emplace_back(gl::to_string(m));
  for (analysis::EnginePolicy p : options.policies) layout.entries.emplace_back(analysis::to_string(p));
  if (options.switch_policy) layout.entries.emplace_back("policy");
  MeshCache meshes;
  options.meshes = &meshes;
  LightSetupCache light_setups;
  options.light_setups = &light_setups;
  const Configurations configurations(o, &meshes);
  meshes.decide_outward_solids();
  const std::uint64_t total = configurations.count();
  MpiWorld* const world_ptr = mpi_world();  // made by main
  NEARCAP_CHECK(world_ptr != nullptr);
  MpiWorld& world = *world_ptr;
  {
    // Rank 0 checks on its machine and every rank gets the verdict, so that
    // all stop together (ranks on other machines may count other cores).
    std::string refused;
    if (world.rank() == 0) {
      const auto [source, width, height] = configurations.largest_frame();
      const std::uint64_t at_once = std::clamp<std::uint64_t>(
          total, 1, static_cast<std::uint64_t>(std::max(1, tbb::this_task_arena::max_concurrency())));
      try {
        check_memory_estimate(
            source, width, height,
            "sweep (" + std::to_string(at_once) + " configuration" + (at_once > 1 ? "s" : "") + " at once)",
            kSweepBytesPerPixel * static_cast<double>(at_once), o.max_memory_gb, "lower --width/--height");
      } catch (const Error& e) {
        if (e.kind() != ErrorKind::Resource) throw;
        refused = e.what();
      }
    }
    if (world.broadcast(refused.empty() ? 0 : 1) != 0) throw Error(ErrorKind::Resource, refused);
  }

  // Rank 0 owns the file: new, or resumed after its last whole configuration.
  constexpr std::uint64_t kFailed = ~std::uint64_t{0};
  std::uint64_t first = 0;
  int fd = -1;
  if (world.rank() == 0) {
    try {
      struct stat st {};
      if (::stat(o.out.c_str(), &st) == 0) {
        if (!S_ISREG(st.st_mode)) refuse_special(o.out, st.st_mode);
      } else if (errno != ENOENT) {
        throw Error(ErrorKind::Io, o.out + ": cannot use it: " + std::strerror(errno));
      } else if (::lstat(o.out.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        // link() would not follow it: the name is taken, the file it names is not there.
        throw Error(ErrorKind::Io, o.out +
                                       ": a symbolic link to a file that does not exist; remove the link, or "
                                       "give the file it names as --out");
      }
      const analysis::SweepMeta meta = sweep_meta(o, options, layout, &meshes);
      const std::string exists = o.out + ": exists; give --resume to continue that sweep, or another --out";
      fd = open_existing(o.out);
      bool resuming = fd >= 0;
      if (resuming && !o.resume) {
        ::close(fd);
        throw Error(ErrorKind::Usage, exists);
      }
      if (!resuming) {
        fd = create_csv(o.out, meta);
        if (fd < 0) {  // another sweep made it since open_existing
          if (!o.resume) throw Error(ErrorKind::Usage, exists);
          fd = open_existing(o.out);
          if (fd < 0) throw Error(ErrorKind::Io, o.out + ": appeared and vanished while this sweep opened it");
          resuming = true;
        }
      }
      if (resuming) {
        lock_csv(fd, o.out);
        try {
          first = resume_point(fd, o.out, configurations, layout, options, meta, o.repair);
        } catch (...) {
          ::close(fd);
          throw;
        }
      }
    } catch (...) {
      world.broadcast(kFailed);
      throw;
    }
  }
  first = world.broadcast(first);
  if (first == kFailed) throw ExitCode{2};  // rank 0 reported why
  world.mark_sharded();

  std::vector<std::uint64_t> mine;
  for (std::uint64_t k = first + static_cast<std::uint64_t>(world.rank()); k < total;
       k += static_cast<std::uint64_t>(world.size()))
    mine.push_back(k);
  std::unique_ptr<OrderedWriter> writer;
  if (world.rank() == 0)
    writer = std::make_unique<OrderedWriter>(
        fd, o.out, first, total, options.methods.size() + options.policies.size() + (options.switch_policy ? 1 : 0));
  if (world.size() == 1) {
    // One process: a pipeline that hands out this rank's configurations in
    // order, computes them on every core (each one's own parallel loops
    // isolated, so that a core waiting in them never takes up another
    // configuration), and writes their rows in order, at most two per core
    // in flight.  Nothing throws inside it, and each configuration runs in
    // a task context of its own, so no configuration is cut short: one that
    // fails (or a write that fails) stops the handing out, the rows of the
    // configurations before it are written, none after it, and its error is
    // thrown here.
    struct Computed {
      std::size_t k = 0;
      std::string rows;
      std::exception_ptr error;
    };
    std::size_t next = 0;
    std::atomic<bool> stop{false};
    std::exception_ptr failure;
    const auto in_flight = static_cast<std::size_t>(2 * tbb::this_task_arena::max_concurrency());
    tbb::parallel_pipeline(
        in_flight,
        tbb::make_filter<void,
                         std::size_t>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) -> std::size_t {
          if (next >= mine.size() || stop.load()) {
            fc.stop();
            return 0;
          }
          return next++;
        }) & tbb::make_filter<std::size_t, Computed>(tbb::filter_mode::parallel, [&](std::size_t k) {
          Computed c;
          c.k = k;
          try {
            // In a context of its own, which nothing cancels.
            tbb::task_group_context own(tbb::task_group_context::isolated);
            tbb::task_group group(own);
            group.run_and_wait([&] {
              tbb::this_task_arena::isolate([&] { c.rows = configuration_csv(configurations.at(mine[k]), options); });
            });
          } catch (...) {
            c.error = std::current_exception();
            stop = true;
          }
          return c;
        }) & tbb::make_filter<Computed, void>(tbb::filter_mode::serial_in_order, [&](Computed c) {
          if (failure) return;
          try {
            if (c.error) std::rethrow_exception(c.error);
            writer->add(mine[c.k], std::move(c.rows));
          } catch (...) {
            failure = std::current_exception();
            stop = true;
          }
        }));
    if (failure) std::rethrow_exception(failure);
  }
  // Under MPI: blocks of configurations run together on this rank's cores,
  // and between blocks the main thread sends or collects rows (MPI is
  // called from that thread alone, as MPI_Init allows).
  constexpr std::size_t kBlock = 8;
  for (std::size_t begin = 0; world.size() > 1 && begin < mine.size(); begin += kBlock) {
    const std::size_t end = std::min(mine.size(), begin + kBlock);
    std::vector<std::string> blocks(end - begin);
    tbb::parallel_for(
        begin, end, [&](std::size_t k) { blocks[k - begin] = configuration_csv(configurations.at(mine[k]), options); });
    for (std::size_t k = begin; k < end; ++k) {
      if (writer)
        writer->add(mine[k], std::move(blocks[k - begin]));
      else
        world.send_rows(mine[k], blocks[k - begin]);
    }
    std::uint64_t index = 0;
    std::string rows;
    while (writer && world.receive_rows(index, rows, false)) writer->add(index, std::move(rows));
  }
  if (!writer) return;
  std::uint64_t index = 0;
  std::string rows;
  while (!writer->complete() && world.receive_rows(index, rows, true)) writer->add(index, std::move(rows));
  if (!writer->complete())
    throw Error(ErrorKind::Io, o.out + ": the sweep ended before every configuration's rows arrived");
  writer->finish();
}

}  // namespace

void register_sample(CLI::App& app) {
  auto [cmd, o] =
      add_subcommand<SampleOptions>(app, "sample", "one hard-case configuration of the sampler as a scene file",
                                    [](const SampleOptions& s) { run_sample(s.sampler, s.index, s.out); });
  add_sampler_options(cmd, o.sampler, true);
  cmd.add_option("--index", o.index, "configuration index (0, 1, ...)")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()))
      ->required();
  cmd.add_option("--out", o.out, "write the scene file here (default: stdout)");
}

void register_sweep(CLI::App& app) {
  auto [cmd, o] = add_subcommand<SweepCommandOptions>(
      app, "sweep",
      "camera paths and hard-case samples through the exact reference and the float methods: one CSV row per "
      "configuration, light and method (docs/sweeps-and-report.md)",
      run_sweep);
  cmd.add_option("--path", o.paths, "a camera path file (repeatable)");
  add_samples_option(cmd, o.samples, "this many hard-case configurations from the sampler", 0, kMaxSweepSamples);
  add_sampler_options(cmd, o.sampler, false);
  add_viewport_options(cmd, o.width, o.height, " (default: the path's; 48 sampled)",
                       " (default: the path's; 36 sampled)");
  cmd.add_option("--methods", o.methods, "comma-separated methods, or all")->capture_default_str();
  cmd.add_option("--policies", o.policies,
                 "engine rules run beside the methods, one row each: comma-separated " +
                     names_joined<analysis::EnginePolicy>() +
                     ", policy (the switch policy of --policy), or all, or none")
      ->capture_default_str();
  note_given(
      cmd.add_option("--policy", o.policy_file, "the switch policy for --policies policy (nearcap tune writes one)"),
      o.policy_given)
      ->capture_default_str();
  add_emulation_options(cmd, o.emulation);
  cmd.add_option("--variant", o.variants,
                 "run every method under these choices too, NAME=VALUE[,...] over the options above "
                 "(repeatable; e.g. light-projection=glfrustum,l-near-scale=0.5)");
  cmd.add_option("--out", o.out, "the results CSV")->required();
  add_max_memory_option(cmd, o.max_memory_gb);
  cmd.add_flag("--resume", o.resume, "continue the sweep already in --out (docs/sweep-files.md)");
  cmd.add_flag("--repair", o.repair,
               "with --resume: remove a configuration cut off mid-write at the end of --out and run it again");
}

}  // namespace nearcap::cli
