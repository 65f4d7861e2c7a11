// Fitting the switch policy's crack model with Ceres (see policy_fit.hpp).
#include "nearcap/analysis/policy_fit.hpp"

#include <ceres/ceres.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "ceres_solve.hpp"
#include "nearcap/analysis/sweep_file.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/input_files.hpp"
#include "nearcap/io/utf8_text.hpp"

namespace nearcap::analysis {
namespace {

// The next line of `in` (its newline dropped) into `line`, through `buffer`
// (kMaxSweepLineBytes + 1 bytes); false at the end.  A longer line is a Parse
// error naming `file` and line `number`, read no further.
bool next_line(std::istream& in, std::vector<char>& buffer, std::string& line, const std::string& file,
               std::size_t number) {
  in.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  const auto count = static_cast<std::size_t>(in.gcount());
  if (in.bad()) throw Error(ErrorKind::Io, file + ": cannot read the sweep CSV");
  if (count == 0 && in.eof()) return false;
  if (in.fail() && !in.eof())
    throw Error(ErrorKind::Parse, file + ": line " + std::to_string(number) + ": longer than " +
                                      std::to_string(kMaxSweepLineBytes >> 20) +
                                      " MB (a sweep row is under 1 kB: not a nearcap sweep CSV)");
  line.assign(buffer.data(), in.eof() ? count : count - 1);  // without the newline getline took
  return true;
}

// One line of a CSV written by nearcap sweep: commas, fields quoted when they
// hold a comma or a quote, quotes doubled.  `closed` is false when a quoted
// field runs to the end of the line (the sweep writes no line breaks in fields).
std::vector<std::string> csv_fields(const std::string& line, bool& closed) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted) {
      if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
        out.back() += '"';
        ++k;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  closed = !quoted;
  return out;
}

// One data row of a sweep CSV: its fields, the header's column indices, and
// where it is (file and line) for errors naming the column.
struct Row {
  const std::vector<std::string>& fields;
  const std::map<std::string, std::size_t>& column;
  const std::string& source;
  std::size_t line;

  const std::string& at(const char* name) const { return fields[column.at(name)]; }
  std::string where() const { return source + ": line " + std::to_string(line); }
  [[noreturn]] void fail(ErrorKind kind, const char* name, const std::string& what) const {
    throw Error(kind, where() + ": column '" + name + "': " + what);
  }
  // A number as the sweep writes it; nan, inf and -inf too (the conditioning
  // columns hold them where a quantity is undefined).
  double number(const char* name) const {
    const std::string& s = at(name);
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    // Decimal as the sweep writes it: no sign '+', no hexadecimal, no other
    // spelling of infinity or nan than the three above.
    if (s.empty() || s.front() == '+' || s.find_first_not_of("0123456789.eE+-") != std::string::npos)
      fail(ErrorKind::Parse, name, "'" + s + "' is not a number");
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size()) fail(ErrorKind::Parse, name, "'" + s + "' is not a number");
    // Out of double's range: beyond its largest, or so small that it reads as
    // 0 (the sweep writes 0 as 0).
    if (!std::isfinite(v) || (errno == ERANGE && (std::fabs(v) == HUGE_VAL || v == 0)))
      fail(ErrorKind::Parse, name, "'" + s + "' is not a number the sweep writes (nan, inf, -inf or a finite one)");
    return v;
  }
  // A time or a count: finite and not negative.
  double measure(const char* name) const {
    const double v = number(name);
    if (!std::isfinite(v)) fail(ErrorKind::NonFinite, name, "'" + at(name) + "' is not a finite number");
    if (v < 0) fail(ErrorKind::Parse, name, "'" + at(name) + "' is negative");
    return v;
  }
  // A ratio of lengths or a condition number: nan where undefined, inf
  // where unbounded, never negative.
  double magnitude(const char* name) const {
    const double v = number(name);
    if (v < 0)
      fail(ErrorKind::Parse, name, "'" + at(name) + "' is negative (the sweep writes no negative " + name + ")");
    return v;
  }
  // A count, in decimal digits as the sweep writes it (no exponent, no
  // point), up to 2^53 (what a double the fits sum it in holds exactly).
  std::size_t count(const char* name) const {
    const std::string& s = at(name);
    if (s == "nan" || s == "inf" || s == "-inf") fail(ErrorKind::NonFinite, name, "'" + s + "' is not a finite number");
    if (!s.empty() && s.front() == '-' && s.size() > 1 && s.find_first_not_of("0123456789", 1) == std::string::npos)
      fail(ErrorKind::Parse, name, "'" + s + "' is negative");
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
      fail(ErrorKind::Parse, name, "'" + s + "' is not a whole number as the sweep writes it");
    const std::size_t digits = s.size() - std::min(s.find_first_not_of('0'), s.size() - 1);
    if (digits > 16 || std::stoull(s) > (std::size_t{1} << 53))
      fail(ErrorKind::Parse, name, "'" + s + "' is over 2^53 (not a count a sweep writes)");
    return std::stoull(s);
  }
  // A flag: 0 or 1.
  bool flag(const char* name) const {
    const std::string& s = at(name);
    if (s != "0" && s != "1") fail(ErrorKind::Parse, name, "'" + s + "' is not 0 or 1");
    return s == "1";
  }
};

// A sweep CSV to read: a file, streamed line by line within the input limit
// (io/input_files.hpp), or text already in memory (text != nullptr).
struct CsvInput {
  std::string source;
  const std::string* text = nullptr;
};

// Field `column` of line `line` of an input read before (a line the reader
// accepted: one record on one line).
std::string field_on_line(const CsvInput& input, std::size_t line, std::size_t column) {
  std::ifstream stream;
  std::istringstream memory;
  std::istream* in = &memory;
  if (input.text) {
    memory.str(*input.text);
  } else {
    stream.open(input.source, std::ios::binary);
    in = &stream;
  }
  std::string text;
  for (std::size_t k = 0; k < line && std::getline(*in, text); ++k) {
  }
  bool closed = true;
  const std::vector<std::string> fields = csv_fields(text, closed);
  return column < fields.size() ? fields[column] : std::string();
}

// Where a configuration's rows were first read.
struct RowPlace {
  std::uint32_t input = 0;
  std::uint32_t column = 0;  // of the configuration id in that input
  std::uint64_t line = 0;
};

// Calls visit for every row of the inputs, after checking each header holds
// the needed columns.  Every line is checked as it is read: UTF-8, closed
// quotes, as many fields as the header; errors name the file and the line.
template <class Visit>
void for_each_row(const std::vector<CsvInput>& inputs, std::initializer_list<const char*> needed, Visit&& visit) {
  // Each configuration's rows together, each (light, method, variant) once,
  // as nearcap sweep writes them: a row repeated, a CSV given twice, or two
  // sweeps whose configurations share ids (a seed, a path's name) would
  // mix or count twice in the fits.  The configurations already passed are
  // kept by the 64-bit hash of their id; a hash met again is confirmed on
  // the line it was first read (two ids of one hash are no error).
  std::unordered_map<std::uint64_t, RowPlace> passed;
  std::string current;
  RowPlace current_place;
  std::set<std::string> current_rows;
  std::uint32_t input_index = 0;
  const auto check_once = [&](const Row& row) {
    const std::string& id = row.at("configuration");
    if (id.empty()) row.fail(ErrorKind::Parse, "configuration", "is empty");
    if (id != current) {
      if (!current.empty()) passed.emplace(fnv1a_64(current), current_place);
      const auto seen = passed.find(fnv1a_64(id));
      if (seen != passed.end() &&
          field_on_line(inputs[seen->second.input], seen->second.line, seen->second.column) == id)
        throw Error(ErrorKind::Parse, row.where() + ": configuration '" + id + "' again, after other configurations (" +
                                          inputs[seen->second.input].source + ": line " +
                                          std::to_string(seen->second.line) +
                                          "): a row repeated, a CSV given twice, or two sweeps whose configurations "
                                          "share ids (the same seed, or paths of the same name); a configuration's "
                                          "rows come together, as nearcap sweep writes them");
      current = id;
      current_place = {input_index, static_cast<std::uint32_t>(row.column.at("configuration")),
                       static_cast<std::uint64_t>(row.line)};
      current_rows.clear();
    }
    const std::string key = row.at("light") + '\0' + row.at("method") + '\0' + row.at("variant");
    if (!current_rows.insert(key).second)
      throw Error(ErrorKind::Parse, row.where() + ": a second row of configuration '" + id + "', light " +
                                        row.at("light") + ", method " + row.at("method") + ", variant " +
                                        row.at("variant"));
  };
  for (const CsvInput& input : inputs) {
    input_index = static_cast<std::uint32_t>(&input - inputs.data());
    const std::string& file = input.source;
    std::ifstream stream;
    std::istringstream memory;
    std::istream* in = &memory;
    std::uint64_t limit = std::numeric_limits<std::uint64_t>::max();
    if (input.text) {
      memory.str(*input.text);
    } else {
      limit = io::max_input_bytes();
      (void)io::check_input_file(file, "sweep CSV");
      stream.open(file, std::ios::binary);
      if (!stream) throw Error(ErrorKind::Io, file + ": cannot open the sweep CSV");
      in = &stream;
    }
    std::string line;
    std::uint64_t read = 0;
    std::size_t number = 0;
    std::vector<std::string> header;
    std::map<std::string, std::size_t> column;
    bool grouped = false;
    std::vector<char> buffer(kMaxSweepLineBytes + 1);
    while (next_line(*in, buffer, line, file, number + 1)) {
      ++number;
      read += line.size() + 1;
      if (read > limit && read - limit > 1)  // the file grew while being read (its last line may lack a newline)
        throw Error(ErrorKind::Resource, file + ": the sweep CSV grew past the input limit of " +
                                             std::to_string(limit >> 20) + " MB while being read");
      const std::string where = file + ": line " + std::to_string(number);
      if (const std::size_t bad = io::first_non_utf8(line); bad != std::string::npos) {
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(line[bad])));
        throw Error(ErrorKind::Parse, where + ": not UTF-8 (byte " + byte + " at column " + std::to_string(bad + 1) +
                                          "; a sweep CSV is UTF-8 text)");
      }
      if (const std::size_t cr = line.find('\r'); cr != std::string::npos && cr + 1 != line.size())
        throw Error(ErrorKind::Parse,
                    where + ": a carriage return inside the line at column " + std::to_string(cr + 1) +
                        " (lines ended by a carriage return alone? a sweep CSV's lines end in a line feed)");
      if (number > 1 && line.empty()) continue;
      // A byte order mark (a spreadsheet's UTF-8 export) is not part of the first column's name.
      if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
      bool closed = true;
      std::vector<std::string> fields = csv_fields(line, closed);
      if (!closed) throw Error(ErrorKind::Parse, where + ": a quoted field is not closed on its line");
      if (number == 1) {
        header = std::move(fields);
        for (std::size_t k = 0; k < header.size(); ++k)
          if (!column.emplace(header[k], k).second)
            throw Error(ErrorKind::Parse, where + ": column '" + header[k] + "' appears twice in the header");
        grouped =
            column.count("configuration") && column.count("light") && column.count("method") && column.count("variant");
        for (const char* c : needed)
          if (!column.count(c))
            throw Error(ErrorKind::Schema,
                        where + ": missing column '" + c + "' (not a nearcap sweep CSV, or one from an older nearcap)");
        continue;
      }
      if (fields.size() != header.size())
        throw Error(ErrorKind::Parse, where + ": " + std::to_string(fields.size()) + " fields, the header has " +
                                          std::to_string(header.size()));
      const Row row{fields, column, file, number};
      if (grouped) check_once(row);
      visit(row);
    }
    if (!input.text && stream.bad()) throw Error(ErrorKind::Io, file + ": cannot read the sweep CSV");
    if (number == 0) throw Error(ErrorKind::Parse, file + ": empty, not a nearcap sweep CSV");
  }
}

std::vector<CsvInput> file_inputs(const std::vector<std::string>& files) {
  std::vector<CsvInput> out;
  for (const std::string& f : files) out.push_back({f, nullptr});
  return out;
}

// The logistic sample's cost: 2 logloss as a squared residual.
struct LogLoss {
  LogLoss(const std::vector<double>& x, int y) : x_(x), sign_(y ? 1.0 : -1.0) {}
  template <class T>
  bool operator()(T const* const* parameters, T* residual) const {
    const T* w = parameters[0];
    T z = parameters[1][0];
    for (std::size_t k = 0; k < x_.size(); ++k) z += w[k] * x_[k];
    const T m = -sign_ * z;  // logloss = softplus(m), computed stably
    using std::exp;
    using std::log;
    using std::sqrt;
    // Two branches that agree in value and slope at 0 (a max(m, 0) + abs(m)
    // form gives the wrong slope there, where every fit starts).
    const T softplus = m >= T(0) ? m + log(T(1) + exp(-m)) : log(T(1) + exp(m));
    // A floor under the square root: a sample classified beyond doubt has a
    // softplus that underflows to 0, where the root's slope is infinite.
    residual[0] = sqrt(T(2) * softplus + T(1e-200));
    return true;
  }
  std::vector<double> x_;
  double sign_;
};

struct Ridge {
  Ridge(std::size_t n, double l2) : n_(n), l2_(l2) {}
  template <class T>
  bool operator()(T const* const* parameters, T* residual) const {
    for (std::size_t k = 0; k < n_; ++k) residual[k] = T(l2_) * parameters[0][k];
    return true;
  }
  std::size_t n_;
  double l2_;
};

std::uint32_t fnv1a(const std::string& s) {
  std::uint32_t h = 2166136261u;
  for (unsigned char c : s) {
    h ^= c;
    h *= 16777619u;
  }
  return h;
}

}  // namespace

bool held_out_configuration(const std::string& configuration_id) { return fnv1a(configuration_id) % 5 == 0; }

namespace {

std::vector<PolicySample> policy_samples_of(const std::vector<CsvInput>& inputs, gl::ShadowMethod capped,
                                            gl::ShadowMethod fallback, const std::string& variant) {
  struct Pair {
    std::optional<std::size_t> capped_cracks, fallback_cracks;
    ConditioningFeatures features;
    bool capped_fell_back = false;
  };
  std::map<std::pair<std::string, std::size_t>, Pair> pairs;
  const std::string capped_name(gl::to_string(capped)), fallback_name(gl::to_string(fallback));
  for_each_row(
      inputs,
      {"configuration", "light", "method", "variant", "pixels_seen", "wrong", "cracks", "fallback", "refused",
       "light_frustum_defined", "light_near_distance", "l_far_over_width", "delta_over_width", "skew",
       "cond_light_transform", "cap_window_error_px", "coordinate_over_size", "l_near_over_l_far"},
      [&](const Row& row) {
        // Every row's flag and counts, as the report reads them, whichever rows the fit takes.
        const bool refused = row.flag("refused");
        const std::size_t cracks = row.count("cracks"), wrong = row.count("wrong");
        if (wrong > row.count("pixels_seen"))
          row.fail(ErrorKind::Parse, "wrong",
                   std::to_string(wrong) + " wrong pixels of " + row.at("pixels_seen") + " seen (pixels_seen)");
        if (cracks > wrong)
          row.fail(
              ErrorKind::Parse, "cracks",
              std::to_string(cracks) + " cracks of " + row.at("wrong") + " wrong pixels (a crack is a wrong pixel)");
        const std::string& method = row.at("method");
        if ((method != capped_name && method != fallback_name) || row.at("variant") != variant || refused) return;
        Pair& p = pairs[{row.at("configuration"), row.count("light")}];
        if (method == capped_name) {
          p.capped_cracks = cracks;
          p.capped_fell_back = !row.at("fallback").empty();
          ConditioningFeatures& c = p.features;
          c.light_frustum_defined = row.flag("light_frustum_defined");
          c.light_near_distance = row.number("light_near_distance");
          c.l_far_over_width = row.magnitude("l_far_over_width");
          c.delta_over_width = row.magnitude("delta_over_width");
          c.skew = row.magnitude("skew");
          c.cond_light_transform = row.magnitude("cond_light_transform");
          c.cap_window_error_px = row.magnitude("cap_window_error_px");
          c.coordinate_over_size = row.magnitude("coordinate_over_size");
          c.l_near_over_l_far = row.magnitude("l_near_over_l_far");
        } else {
          p.fallback_cracks = cracks;
        }
      });
  std::vector<PolicySample> out;
  for (const auto& [key, p] : pairs) {
    if (!p.capped_cracks || !p.fallback_cracks || p.capped_fell_back) continue;
    PolicySample s;
    s.configuration = key.first;
    s.light = key.second;
    bool finite = true;
    for (std::string_view name : kPolicyFeatures) {
      s.x.push_back(policy_feature(name, p.features));
      finite = finite && std::isfinite(s.x.back());
    }
    if (!finite) continue;
    s.crack = *p.capped_cracks > *p.fallback_cracks;
    s.held_out = held_out_configuration(s.configuration);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<CostSample> cost_samples_of(const std::vector<CsvInput>& inputs, gl::ShadowMethod method,
                                        const std::string& variant) {
  std::vector<CostSample> out;
  const std::string name(gl::to_string(method));
  for_each_row(inputs,
               {"configuration", "method", "variant", "refused", "depth_triangles", "near_cap_triangles",
                "volume_triangles", "depth_fragments", "near_cap_fragments", "volume_fragments", "frame_ms"},
               [&](const Row& row) {
                 const bool refused = row.flag("refused");
                 if (row.at("method") != name || row.at("variant") != variant || refused) return;
                 CostSample s;
                 s.configuration = row.at("configuration");
                 for (const char* c : {"depth_triangles", "near_cap_triangles", "volume_triangles"})
                   s.triangles += row.measure(c);
                 for (const char* c : {"depth_fragments", "near_cap_fragments", "volume_fragments"})
                   s.fragments += row.measure(c);
                 s.ms = row.measure("frame_ms");
                 s.held_out = held_out_configuration(s.configuration);
                 out.push_back(s);
               });
  return out;
}

}  // namespace

std::vector<PolicySample> policy_samples(const std::vector<std::string>& files, gl::ShadowMethod capped,
                                         gl::ShadowMethod fallback, const std::string& variant) {
  return policy_samples_of(file_inputs(files), capped, fallback, variant);
}

std::vector<PolicySample> policy_samples_from_text(const std::string& csv, const std::string& source,
                                                   gl::ShadowMethod capped, gl::ShadowMethod fallback,
                                                   const std::string& variant) {
  return policy_samples_of({{source, &csv}}, capped, fallback, variant);
}

std::vector<CostSample> cost_samples(const std::vector<std::string>& files, gl::ShadowMethod method,
                                     const std::string& variant) {
  return cost_samples_of(file_inputs(files), method, variant);
}

std::vector<CostSample> cost_samples_from_text(const std::string& csv, const std::string& source,
                                               gl::ShadowMethod method, const std::string& variant) {
  return cost_samples_of({{source, &csv}}, method, variant);
}

namespace {
struct CostResidual {
  CostResidual(double mtriangles, double mfragments, double ms) : t_(mtriangles), f_(mfragments), ms_(ms) {}
  template <class T>
  bool operator()(const T* c, T* residual) const {
    residual[0] = c[0] + c[1] * t_ + c[2] * f_ - T(ms_);
    return true;
  }
  double t_, f_, ms_;
};
}  // namespace

CostModel fit_cost_model(const std::vector<CostSample>& samples, bool robust) {
  std::array<double, 3> c{0, 0, 0};
  ceres::Problem problem;
  std::size_t used = 0;
  for (const CostSample& s : samples) {
    if (s.held_out) continue;
    ++used;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CostResidual, 1, 3>(
                                 new CostResidual(s.triangles * 1e-6, s.fragments * 1e-6, s.ms)),
                             robust ? new ceres::CauchyLoss(1.0) : nullptr, c.data());
  }
  if (used < 3) throw Error(ErrorKind::Usage, "a cost model needs at least 3 training rows of the method");
  solve_or_throw(problem, deterministic_solver_options(100), "cost");
  return {c[0], c[1], c[2]};
}

double median_relative_error(const CostModel& model, const std::vector<CostSample>& samples, bool held_out) {
  std::vector<double> e;
  for (const CostSample& s : samples)
    if (s.held_out == held_out && s.ms > 0)
      e.push_back(std::fabs(model.predict_ms(s.triangles, s.fragments) - s.ms) / s.ms);
  if (e.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
  return e[e.size() / 2];
}

LogisticFit fit_logistic(const std::vector<std::vector<double>>& x, const std::vector<int>& y,
                         const LogisticFitOptions& options) {
  if (x.empty() || x.size() != y.size()) throw Error(ErrorKind::Usage, "fit_logistic: no samples, or labels missing");
  const std::size_t n = x.front().size();
  LogisticFit fit;
  fit.mean.assign(n, 0.0);
  fit.scale.assign(n, 0.0);
  for (const auto& row : x)
    for (std::size_t k = 0; k < n; ++k) fit.mean[k] += row[k] / static_cast<double>(x.size());
  for (const auto& row : x)
    for (std::size_t k = 0; k < n; ++k)
      fit.scale[k] += (row[k] - fit.mean[k]) * (row[k] - fit.mean[k]) / static_cast<double>(x.size());
  for (double& s : fit.scale) s = s > 0 ? std::sqrt(s) : 1.0;

  fit.weights.assign(n, 0.0);
  ceres::Problem problem;
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<double> standard(n);
    for (std::size_t k = 0; k < n; ++k) standard[k] = (x[i][k] - fit.mean[k]) / fit.scale[k];
    auto* cost = new ceres::DynamicAutoDiffCostFunction<LogLoss, 8>(new LogLoss(standard, y[i]));
    cost->AddParameterBlock(static_cast<int>(n));
    cost->AddParameterBlock(1);
    cost->SetNumResiduals(1);
    problem.AddResidualBlock(cost, options.robust ? new ceres::HuberLoss(options.huber_delta) : nullptr,
                             fit.weights.data(), &fit.bias);
  }
  if (options.l2 > 0) {
    auto* ridge = new ceres::DynamicAutoDiffCostFunction<Ridge, 8>(new Ridge(n, options.l2));
    ridge->AddParameterBlock(static_cast<int>(n));
    ridge->SetNumResiduals(static_cast<int>(n));
    problem.AddResidualBlock(ridge, nullptr, fit.weights.data());
  }
  ceres::Solver::Options solver = deterministic_solver_options(200);
  // Nearly separable data (a few cracks) send the weights far: bounded steps
  // in standardized units keep every trial point finite.
  solver.initial_trust_region_radius = 1.0;
  solver.max_trust_region_radius = 100.0;
  solver.max_num_consecutive_invalid_steps = 50;
  const ceres::Solver::Summary summary = solve_or_throw(problem, solver, "logistic");
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.final_cost = summary.final_cost;
  return fit;
}

Confusion confusion(const CrackModel& model, const std::vector<PolicySample>& samples, bool held_out) {
  Confusion c;
  for (const PolicySample& s : samples) {
    if (s.held_out != held_out) continue;
    double z = model.bias;
    for (std::size_t k = 0; k < model.weights.size(); ++k)
      z += model.weights[k] * (s.x[k] - model.mean[k]) / model.scale[k];
    const bool predicted = 1.0 / (1.0 + std::exp(-z)) >= model.threshold;
    ++c.samples;
    c.positives += s.crack;
    c.true_positives += s.crack && predicted;
    c.false_positives += !s.crack && predicted;
  }
  return c;
}

std::vector<std::string> unread_policy_models(const SwitchPolicy& policy) {
  std::vector<std::string> unread;
  // Without a profile the model is asked before drawing the capped ZP+ for
  // an occluder the exact test could not give Z-pass; with one (the cost
  // decision) it admits the paper-cap candidate, whatever the exact test.
  const bool paper_cap = policy.light_projection != gl::LightProjection::ClippedSides;
  const bool crack_model_read =
      gl::uses_near_cap(policy.capped_method) && (policy.device_profile ? paper_cap : policy.exact_zpass);
  if (!policy.crack_model.features.empty() && !crack_model_read) unread.push_back("crack_model");
  if (!policy.cost_models.empty()) unread.push_back("cost_models");
  return unread;
}

SwitchPolicy tune_policy(const std::vector<PolicySample>& all_samples, gl::ShadowMethod capped,
                         gl::ShadowMethod fallback, const std::string& command, const LogisticFitOptions& options,
                         const std::vector<std::string>& feature_names, bool crack_model) {
  // The chosen features' columns.
  std::vector<std::string> names = feature_names;
  if (names.empty()) names.assign(kPolicyFeatures.begin(), kPolicyFeatures.end());
  std::vector<std::size_t> columns;
  for (const std::string& name : names) {
    const auto it = std::find(kPolicyFeatures.begin(), kPolicyFeatures.end(), name);
    if (it == kPolicyFeatures.end()) throw Error(ErrorKind::Usage, "'" + name + "' is not a policy feature");
    if (std::count(names.begin(), names.end(), name) > 1)
      throw Error(ErrorKind::Usage, "'" + name + "' is named twice (each feature once)");
    columns.push_back(static_cast<std::size_t>(it - kPolicyFeatures.begin()));
  }
  std::vector<PolicySample> samples = all_samples;
  for (PolicySample& s : samples) {
    std::vector<double> x;
    for (std::size_t c : columns) x.push_back(s.x[c]);
    s.x = std::move(x);
  }
  std::vector<std::vector<double>> x;
  std::vector<int> y;
  for (const PolicySample& s : samples)
    if (!s.held_out) {
      x.push_back(s.x);
      y.push_back(s.crack ? 1 : 0);
    }
  if (x.empty())
    throw Error(ErrorKind::Usage,
                "no training samples: the rows need both methods in the policy's variant (sweep with "
                "--switch-clamp clamp-far, or say which with --variant), the capped one without a fallback and "
                "with every conditioning feature finite");
  SwitchPolicy p;
  p.capped_method = capped;
  p.fallback_method = fallback;
  CrackModel& m = p.crack_model;
  const bool any_crack = std::find(y.begin(), y.end(), 1) != y.end();
  nlohmann::json fit_json;
  if (crack_model && any_crack) {
    const LogisticFit fit = fit_logistic(x, y, options);
    m.features = names;
    m.mean = fit.mean;
    m.scale = fit.scale;
    m.weights = fit.weights;
    m.bias = fit.bias;
    // Every training crack predicted: the smallest positive's probability, halved.
    double lowest = 1.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (y[i]) {
        double z = m.bias;
        for (std::size_t k = 0; k < x[i].size(); ++k) z += m.weights[k] * (x[i][k] - m.mean[k]) / m.scale[k];
        lowest = std::min(lowest, 1.0 / (1.0 + std::exp(-z)));
      }
    m.threshold = std::clamp(lowest / 2, 1e-12, 0.5);
    fit_json = {{"iterations", fit.iterations},
                {"final_cost", fit.final_cost},
                {"robust", options.robust},
                {"huber_delta", options.huber_delta},
                {"l2", options.l2}};
  } else {
    // No model asked for, or no training pair where the capped method
    // cracks more than the fallback: nothing to separate, no fit.  A model
    // without features whose probability, 1 / (1 + e^30), is below any
    // threshold: it never predicts a crack (the held-out side below says
    // whether that holds).
    m.bias = -30;
    m.threshold = 1;
    fit_json = {{"none", crack_model ? "no training pair where the capped method cracks more than the fallback"
                                     : "no crack model asked for (--features none)"}};
  }
  const Confusion train = confusion(m, samples, false), held = confusion(m, samples, true);
  auto side = [](const Confusion& c) {
    return nlohmann::json{{"samples", c.samples},
                          {"cracks", c.positives},
                          {"cracks_predicted", c.true_positives},
                          {"false_alarms", c.false_positives}};
  };
  nlohmann::json prov{{"command", command},
                      {"split", "held out: FNV-1a(configuration) % 5 == 0"},
                      {"fit", fit_json},
                      {"train", side(train)},
                      {"held_out", side(held)}};
  // The command names the CSV files: a name that is not UTF-8 gets U+FFFD.
  p.provenance_json = prov.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return p;
}

}  // namespace nearcap::analysis
