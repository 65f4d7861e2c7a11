// The strict JSON reader (see json_reader.hpp).
#include "nearcap/io/json_reader.hpp"

#include <cmath>
#include <limits>
#include <set>

#include "json_tree.hpp"

namespace nearcap::io {
namespace {

const JsonNode& node_of(const void* node) { return *static_cast<const JsonNode*>(node); }

// The deepest nesting of arrays and objects read.  nearcap's own files nest
// a few levels; a deeper tree is refused while it is parsed, because the
// tree copies a value recursively (an object's member list copies its
// members as it grows), so a value nested tens of thousands deep with a
// member after it would overflow the stack.
constexpr std::size_t kMaxJsonDepth = 64;

// The parser callback.  nlohmann::json keeps the last of two equal keys, so a
// file with one would be read with half of it ignored; here it is a Schema
// error naming the key's path.  It also tracks the path of the value being
// parsed, so that a parse error (1e999 overflows a double) names the field it
// is in.
class KeyTracker {
 public:
  explicit KeyTracker(std::string source) : source_(std::move(source)), state_(std::make_shared<State>()) {}

  bool operator()(int, nlohmann::detail::parse_event_t event, JsonNode& parsed) const {
    using Event = nlohmann::detail::parse_event_t;
    State& st = *state_;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        if (st.open.size() == kMaxJsonDepth)
          throw Error(ErrorKind::Parse, source_ + ": " + path() + ": arrays and objects nested more than " +
                                            std::to_string(kMaxJsonDepth) + " deep (nearcap's files nest a few)");
        next_element(st);
        st.open.push_back({event == Event::array_start, {}, "", -1});
        break;
      case Event::object_end:
      case Event::array_end:
        st.open.pop_back();
        member_done(st);
        break;
      case Event::key: {
        Open& o = st.open.back();
        o.key = parsed.get<std::string>();
        if (!o.keys.insert(o.key).second)
          throw Error(ErrorKind::Schema,
                      source_ + ": " + path() + ": duplicate key (each key may appear once in an object)");
        break;
      }
      case Event::value:
        next_element(st);
        member_done(st);
        break;
    }
    return true;
  }

  // Where the parser is: "crack_model.bias", "crack_model.mean[2]", or
  // "(top level)".
  std::string path() const {
    std::string p;
    const std::vector<Open>& open = state_->open;
    for (std::size_t k = 0; k < open.size(); ++k) {
      const Open& o = open[k];
      // The innermost array's next element is the one being parsed; an outer
      // array's current one holds the containers opened inside it.
      if (o.array)
        p += "[" + std::to_string(k + 1 == open.size() ? o.index + 1 : o.index) + "]";
      else if (!o.key.empty())
        p += (p.empty() ? "" : ".") + o.key;
    }
    return p.empty() ? "(top level)" : p;
  }

 private:
  struct Open {
    bool array;
    std::set<std::string> keys;
    std::string key;  // objects: the current member's
    long index;       // arrays: the current element's
  };
  struct State {
    std::vector<Open> open;
  };
  // A value, object or array starts: in an array it is the next element.
  static void next_element(State& st) {
    if (!st.open.empty() && st.open.back().array) ++st.open.back().index;
  }
  // A value, object or array ends: in an object the parser is past its key
  // (a fault after it is the object's, not the member's).
  static void member_done(State& st) {
    if (!st.open.empty() && !st.open.back().array) st.open.back().key.clear();
  }
  std::string source_;
  std::shared_ptr<State> state_;  // shared: the parser copies the callback
};

// nlohmann's message without its "[json.exception.parse_error.101] " tag.
std::string json_message(const nlohmann::json::exception& e) {
  std::string m = e.what();
  if (m.rfind("[json.exception.", 0) == 0)
    if (const std::size_t end = m.find("] "); end != std::string::npos) m.erase(0, end + 2);
  return m;
}

}  // namespace

JsonValue json_value(std::shared_ptr<const JsonTree> tree, const void* node, std::string path) {
  return JsonValue(std::move(tree), node, std::move(path));
}

JsonValue json_root(JsonNode root, std::string source) {
  auto tree = std::make_shared<JsonTree>(JsonTree{std::move(root), std::move(source)});
  const void* node = &tree->root;
  return json_value(std::move(tree), node, "");
}

JsonDocument JsonDocument::parse(const std::string& text, const std::string& source) {
  auto tree = std::make_shared<JsonTree>();
  tree->source = source;
  const KeyTracker tracker(source);
  try {
    tree->root = JsonNode::parse(text, tracker);
  } catch (const nlohmann::json::exception& e) {
    // parse_error (syntax, ill-formed UTF-8: its message has the line and
    // column) and out_of_range (a number beyond double, 1e999).
    throw Error(ErrorKind::Parse, source + ": " + tracker.path() + ": malformed JSON: " + json_message(e));
  }
  return JsonDocument(std::move(tree));
}

JsonValue JsonDocument::root() const { return JsonValue(tree_, &tree_->root, ""); }

const std::string& JsonValue::source() const { return tree_->source; }

std::string JsonValue::path() const { return path_.empty() ? "(top level)" : path_; }

void JsonValue::fail(ErrorKind kind, const std::string& what) const {
  throw Error(kind, source() + ": " + path() + ": " + what);
}

const char* JsonValue::type_name() const { return node_of(node_).type_name(); }
bool JsonValue::is_object() const { return node_of(node_).is_object(); }
bool JsonValue::is_array() const { return node_of(node_).is_array(); }
bool JsonValue::is_string() const { return node_of(node_).is_string(); }
bool JsonValue::is_number() const { return node_of(node_).is_number(); }
bool JsonValue::is_integer() const { return node_of(node_).is_number_integer(); }
bool JsonValue::is_boolean() const { return node_of(node_).is_boolean(); }

void JsonValue::expect_object() const {
  if (!is_object()) fail("expected a JSON object, found " + std::string(type_name()));
}

void JsonValue::expect_array() const {
  if (!is_array()) fail("expected an array, found " + std::string(type_name()));
}

JsonValue JsonValue::child(std::string_view key, const void* node) const {
  return JsonValue(tree_, node, path_.empty() ? std::string(key) : path_ + "." + std::string(key));
}

JsonValue JsonValue::element(std::size_t index, const void* node) const {
  return JsonValue(tree_, node, path_ + "[" + std::to_string(index) + "]");
}

const JsonValue& JsonValue::only_keys(std::initializer_list<std::string_view> allowed) const {
  return only_keys(std::vector<std::string_view>(allowed));
}

const JsonValue& JsonValue::only_keys(const std::vector<std::string_view>& allowed) const {
  expect_object();
  for (const auto& [key, value] : node_of(node_).items()) {
    bool ok = false;
    for (std::string_view a : allowed) ok = ok || key == a;
    if (ok) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    child(key, &value).fail("unknown key (allowed: " + list + ")");
  }
  return *this;
}

bool JsonValue::has(std::string_view key) const {
  expect_object();
  return node_of(node_).contains(std::string(key));
}

std::optional<JsonValue> JsonValue::find(std::string_view key) const {
  expect_object();
  const JsonNode& n = node_of(node_);
  const auto it = n.find(std::string(key));
  if (it == n.end()) return std::nullopt;
  return child(key, &*it);
}

JsonValue JsonValue::at(std::string_view key) const {
  if (auto v = find(key)) return *v;
  child(key, nullptr).fail("missing required key");
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::members() const {
  expect_object();
  std::vector<std::pair<std::string, JsonValue>> out;
  for (const auto& [key, value] : node_of(node_).items()) out.emplace_back(key, child(key, &value));
  return out;
}

std::size_t JsonValue::size() const {
  expect_array();
  return node_of(node_).size();
}

std::vector<JsonValue> JsonValue::elements() const {
  expect_array();
  const JsonNode& n = node_of(node_);
  std::vector<JsonValue> out;
  for (std::size_t k = 0; k < n.size(); ++k) out.push_back(element(k, &n[k]));
  return out;
}

std::vector<JsonValue> JsonValue::elements(std::size_t n, std::string_view what) const {
  if (!is_array() || node_of(node_).size() != n)
    fail("expected an array of " + std::to_string(n) + " " + std::string(what));
  return elements();
}

double JsonValue::number() const {
  if (!is_number()) fail("expected a number, found " + std::string(type_name()));
  const double v = node_of(node_).get<double>();
  if (!std::isfinite(v)) fail(ErrorKind::NonFinite, "the number is not finite");
  return v;
}

std::vector<double> JsonValue::numbers() const {
  if (!is_array()) fail("expected an array of numbers, found " + std::string(type_name()));
  std::vector<double> out;
  for (const JsonValue& e : elements()) out.push_back(e.number());
  return out;
}

long long JsonValue::integer() const {
  const JsonNode& n = node_of(node_);
  if (n.is_number_float()) {
    // A number written with a fraction or an exponent (1e30, 2.5).
    const double v = n.get<double>();
    if (std::isfinite(v) && v == std::floor(v))
      fail("expected an integer, found " + n.dump() +
           ", a whole number written as a float (write it in digits, "
           "at most " +
           std::to_string(std::numeric_limits<long long>::max()) + ")");
    fail("expected an integer, found a fraction (" + n.dump() + ")");
  }
  if (!n.is_number_integer()) fail("expected an integer, found " + std::string(type_name()));
  if (n.is_number_unsigned() &&
      n.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<long long>::max()))
    fail("the integer " + n.dump() + " is too large");
  return n.get<long long>();
}

long long JsonValue::integer(long long lo, long long hi, std::string_view what) const {
  const JsonNode& n = node_of(node_);
  const std::string expected = "expected " + (what.empty() ? std::string("a whole number") : std::string(what)) +
                               " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!n.is_number_integer()) fail(expected + ", found " + (n.is_number() ? n.dump() : type_name()));
  const bool beyond = n.is_number_unsigned() &&
                      n.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<long long>::max());
  if (beyond || n.get<long long>() < lo || n.get<long long>() > hi) fail(expected + ", found " + n.dump());
  return n.get<long long>();
}

std::uint64_t JsonValue::count() const {
  const JsonNode& n = node_of(node_);
  if (!n.is_number_unsigned())
    fail("expected a count (a whole number, not negative), found " + (n.is_number() ? n.dump() : type_name()));
  return n.get<std::uint64_t>();
}

std::string JsonValue::string() const {
  if (!is_string()) fail("expected a string, found " + std::string(type_name()));
  return node_of(node_).get<std::string>();
}

bool JsonValue::boolean() const {
  if (!is_boolean()) fail("expected true or false, found " + std::string(type_name()));
  return node_of(node_).get<bool>();
}

std::string JsonValue::dump() const {
  // Keys sorted, as nlohmann::json writes them, whatever order the file had.
  return nlohmann::json(node_of(node_)).dump();
}

std::string JsonValue::must_be(const std::vector<std::string_view>& names) {
  std::string s;
  for (std::size_t k = 0; k < names.size(); ++k)
    s += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + ("\"" + std::string(names[k]) + "\"");
  return "must be " + s;
}

template <>
double JsonValue::get<double>() const {
  return number();
}
template <>
long long JsonValue::get<long long>() const {
  return integer();
}
template <>
std::uint64_t JsonValue::get<std::uint64_t>() const {
  return count();
}
template <>
std::string JsonValue::get<std::string>() const {
  return string();
}
template <>
bool JsonValue::get<bool>() const {
  return boolean();
}
template <>
JsonValue JsonValue::get<JsonValue>() const {
  return *this;
}

}  // namespace nearcap::io
