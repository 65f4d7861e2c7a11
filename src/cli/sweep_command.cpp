// nearcap sweep: camera paths and hard-case samples through the exact
// reference and the float methods, one CSV row per (configuration, light,
// method).  nearcap sample: one hard-case configuration as a scene file.
//
// Configurations are enumerated in a fixed order (each --path's frames, then
// sampler indices 0..N-1) and run a few at a time on all cores; each
// configuration's rows are appended to the CSV in one write, in order.  With
// --resume an existing CSV is continued: its last configuration is run again
// (it may have been cut off mid-write), every earlier one is kept, so no row
// is lost or written twice.
#include <fcntl.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "cli_commands.hpp"
#include "mpi_world.hpp"
#include "nearcap/analysis/camera_path.hpp"
#include "nearcap/analysis/hard_case_sampler.hpp"
#include "nearcap/analysis/sweep.hpp"
#include "nearcap/check.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"

namespace nearcap::cli {
namespace {

std::string sample_replay(const SamplerOptions& o, std::uint64_t index) {
  std::ostringstream s;
  s << "nearcap sample --seed " << o.seed << " --index " << index << " --kinds " << o.kinds << " --width " << o.width
    << " --height " << o.height << (o.allow_bunny ? " --allow-bunny" : "") << " --out c.json";
  return s.str();
}

// ---- nearcap sample --------------------------------------------------------

void run_sample(const SamplerOptions& o, std::uint64_t index, const std::string& out) {
  const analysis::HardCase c = analysis::HardCaseSampler(sampler_spec(o)).sample(index);
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
  std::string policy_file = std::string(NEARCAP_DATA_DIR) + "/policy.json";
  EmulationOptions emulation;
  std::vector<std::string> variants;
  std::string out;
  bool resume = false;
};

// The configurations in their fixed order, made on demand.
class Configurations {
 public:
  explicit Configurations(const SweepCommandOptions& o) : options_(o) {
    for (const std::string& file : o.paths) {
      analysis::CameraPath path = analysis::load_camera_path(file);
      if (o.width > 0) path.width = o.width;
      if (o.height > 0) path.height = o.height;
      paths_.push_back(std::move(path));
    }
    analysis::SamplerSpec spec = sampler_spec(o.sampler);
    if (o.width > 0) spec.width = o.width;
    if (o.height > 0) spec.height = o.height;
    sampler_options_ = o.sampler;
    sampler_options_.width = spec.width;
    sampler_options_.height = spec.height;
    sampler_ = std::make_unique<analysis::HardCaseSampler>(spec);
    for (const analysis::CameraPath& p : paths_) count_ += static_cast<std::uint64_t>(p.frames);
    count_ += o.samples;
  }
  std::uint64_t count() const { return count_; }

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
        c.scene_json = analysis::path_frame_json(p, f);
        c.replay = "nearcap frame " + p.source + " --frame " + std::to_string(f) + " --width " +
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

// --resume: the configurations already in the CSV, all but its last (which is
// run again).  The file is cut back to the end of the previous one.
std::uint64_t resume_point(const std::string& file, const Configurations& configurations) {
  const std::string text = io::read_input_file(file, "sweep results file");
  const std::string header = analysis::csv_header();
  if (text.compare(0, header.size(), header) != 0)
    throw Error(ErrorKind::Schema, file +
                                       ": not a sweep results file of this nearcap (its header differs); "
                                       "start a new one or remove --resume");
  // Line starts of each configuration's first row, in file order.
  std::vector<std::pair<std::string, std::size_t>> starts;
  std::size_t pos = header.size();
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;  // a cut-off last line
    std::string id = text.substr(pos, text.find(',', pos) - pos);
    if (!id.empty() && id.front() == '"') id = id.substr(1, id.size() - 2);
    if (starts.empty() || starts.back().first != id) starts.emplace_back(id, pos);
    pos = end + 1;
  }
  if (starts.empty()) {
    ::truncate(file.c_str(), static_cast<off_t>(header.size()));
    return 0;
  }
  // Every kept configuration must be the next one in order: same options.
  for (std::size_t k = 0; k + 1 < starts.size(); ++k)
    if (k >= configurations.count() || configurations.at(k).id != starts[k].first)
      throw Error(ErrorKind::Schema, file + ": row group " + std::to_string(k) + " is configuration '" +
                                         starts[k].first + "', not what these options make ('" +
                                         (k < configurations.count() ? configurations.at(k).id : "none") +
                                         "'); resume with the options of the interrupted run");
  if (::truncate(file.c_str(), static_cast<off_t>(starts.back().second)) != 0)
    throw Error(ErrorKind::Io, file + ": cannot cut the last configuration back for the resume");
  return starts.size() - 1;
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
  OrderedWriter(const std::string& file, std::uint64_t first, std::uint64_t total, std::size_t methods)
      : file_(file), first_(first), next_(first), total_(total), last_report_(first) {
    fd_ = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd_ < 0) throw Error(ErrorKind::Io, file + ": cannot open for appending");
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
      write_all(it->second);
      ready_.erase(it);
      ++next_;
    }
    if (next_ != before) progress();
  }
  bool complete() const { return next_ == total_; }
  void finish() const {
    const double seconds = elapsed();
    if (terminal_) std::fprintf(stderr, "\n");
    std::printf("sweep: %llu configurations in %.1f s (%.2f per second), rows in %s\n",
                static_cast<unsigned long long>(total_ - first_), seconds,
                static_cast<double>(total_ - first_) / std::max(seconds, 1e-9), file_.c_str());
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  void write_all(const std::string& b) {
    std::size_t written = 0;
    while (written < b.size()) {
      const ssize_t n = ::write(fd_, b.data() + written, b.size() - written);
      if (n < 0) throw Error(ErrorKind::Io, file_ + ": write failed: " + std::strerror(errno));
      written += static_cast<std::size_t>(n);
    }
  }
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
  std::size_t start = 0;
  while (start <= names.size()) {
    const std::size_t comma = std::min(names.find(',', start), names.size());
    const std::string name = names.substr(start, comma - start);
    const auto p = analysis::engine_policy_from_string(name);
    if (name == "policy") {
      switch_policy = true;
    } else if (!p) {
      throw Error(
          ErrorKind::Usage,
          "--policies '" + name + "' is not one of doom3, doom3-bfg, ogre, always-zfail, policy (or all, or none)");
    } else {
      out.push_back(*p);
    }
    start = comma + 1;
  }
  return out;
}

void run_sweep(const SweepCommandOptions& o) {
  if (o.paths.empty() && o.samples == 0)
    throw Error(ErrorKind::Usage, "nothing to sweep: give --path FILE (repeatable) and/or --samples N");
  analysis::SweepOptions options;
  options.methods = methods_from(o.methods, "--methods");
  bool switch_policy = false;
  options.policies = policies_from(o.policies, switch_policy);
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
  MeshCache meshes;
  options.meshes = &meshes;
  const Configurations configurations(o);
  const std::uint64_t total = configurations.count();
  MpiWorld* const world_ptr = mpi_world();  // made by main
  NEARCAP_CHECK(world_ptr != nullptr);
  MpiWorld& world = *world_ptr;

  // Rank 0 owns the file: new, or resumed after its last configuration.
  constexpr std::uint64_t kFailed = ~std::uint64_t{0};
  std::uint64_t first = 0;
  if (world.rank() == 0) {
    try {
      const bool exists = std::filesystem::exists(o.out);
      if (exists && !o.resume)
        throw Error(ErrorKind::Usage, o.out + ": exists; give --resume to continue that sweep, or another --out");
      if (exists)
        first = resume_point(o.out, configurations);
      else
        io::write_output_files({{o.out, analysis::csv_header()}});
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
        o.out, first, total, options.methods.size() + options.policies.size() + (options.switch_policy ? 1 : 0));
  constexpr std::size_t kBlock = 8;  // run together on this rank's cores
  for (std::size_t begin = 0; begin < mine.size(); begin += kBlock) {
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
  auto* cmd = app.add_subcommand("sample", "one hard-case configuration of the sampler as a scene file");
  auto o = std::make_shared<SamplerOptions>();
  auto index = std::make_shared<std::uint64_t>(0);
  auto out = std::make_shared<std::string>();
  add_sampler_options(*cmd, *o, true);
  cmd->add_option("--index", *index, "configuration index (0, 1, ...)")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()))
      ->required();
  cmd->add_option("--out", *out, "write the scene file here (default: stdout)");
  cmd->callback([o, index, out] { run_sample(*o, *index, *out); });
}

void register_sweep(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep",
      "camera paths and hard-case samples through the exact reference and the float methods: one CSV row per "
      "configuration, light and method (README \"Sweeps\")");
  auto o = std::make_shared<SweepCommandOptions>();
  cmd->add_option("--path", o->paths, "a camera path file (repeatable)");
  cmd->add_option("--samples", o->samples, "this many hard-case configurations from the sampler")
      ->transform(integer_in(0, kMaxSweepSamples));
  add_sampler_options(*cmd, o->sampler, false);
  cmd->add_option("--width", o->width, "viewport width of every configuration (default: the path's; 48 sampled)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd->add_option("--height", o->height, "viewport height of every configuration (default: the path's; 36 sampled)")
      ->transform(integer_in(1, kMaxViewportPixels));
  cmd->add_option("--methods", o->methods, "comma-separated methods, or all")->capture_default_str();
  cmd->add_option("--policies", o->policies,
                  "engine rules run beside the methods, one row each: comma-separated doom3, doom3-bfg, ogre, "
                  "always-zfail, policy (the switch policy of --policy), or all, or none")
      ->capture_default_str();
  cmd->add_option("--policy", o->policy_file, "the switch policy for --policies policy (nearcap tune writes one)")
      ->capture_default_str();
  add_emulation_options(*cmd, o->emulation);
  cmd->add_option("--variant", o->variants,
                  "run every method under these choices too, NAME=VALUE[,...] over the options above "
                  "(repeatable; e.g. light-projection=glfrustum,l-near-scale=0.5)");
  cmd->add_option("--out", o->out, "the results CSV")->required();
  cmd->add_flag("--resume", o->resume, "continue the sweep already in --out");
  cmd->callback([o] { run_sweep(*o); });
}

}  // namespace nearcap::cli
