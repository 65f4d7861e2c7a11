// nearcap/io/json_reader.hpp — one strict reader for nearcap's JSON files.
//
// Scene files, camera paths, policies, device profiles and sweep sidecars are
// read through it, so that each fault is reported the same way:
//   SOURCE: PATH: what
// where PATH is the JSON path of the offending value ("objects[2].mesh",
// "crack_model.mean[1]"), or "(top level)" for the document itself.  The kinds:
//   Parse      the text is not JSON (the message has the line and column), or
//              a number lies beyond double's range (1e999); PATH is where the
//              parser was: the member being read, or the object or array past
//              its last complete member;
//   Schema     a duplicate key (nlohmann::json would keep the last silently),
//              an unknown key, a missing required key, a wrong type, a value
//              not in its list of names;
//   NonFinite  a number that is not finite where one is required (JSON text
//              cannot spell one; a number too large for a double is a Parse
//              error above).
// Wording, in the order a reader meets them:
//   PATH: malformed JSON: parse error at line L, column C: ...
//   PATH.key: duplicate key (each key may appear once in an object)
//   PATH.key: unknown key (allowed: a, b, c)
//   PATH.key: missing required key
//   PATH: expected a number, found string
//   PATH: must be "a", "b" or "c", not "d"
// Each file's own checks (ranges, cross-field rules) fail through
// JsonValue::fail, so they name the file and the path the same way.
//
// JsonValue is a view into a parsed document it shares: copies are cheap
// (a shared pointer and the path), and a value outlives the JsonDocument it came from.
// The JSON library stays inside nearcap (this header needs none).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nearcap/error.hpp"

namespace nearcap::io {

struct JsonTree;  // the parsed document (src/io/json_tree.hpp)

class JsonValue {
 public:
  const std::string& source() const;  // the file, as messages name it
  // The JSON path of this value, "(top level)" for the root.
  std::string path() const;

  // Throws Error(kind, "SOURCE: PATH: what").
  [[noreturn]] void fail(ErrorKind kind, const std::string& what) const;
  [[noreturn]] void fail(const std::string& what) const { fail(ErrorKind::Schema, what); }

  // The JSON type, as messages name it: "object", "array", "string",
  // "number", "boolean" or "null".
  const char* type_name() const;
  bool is_object() const;
  bool is_array() const;
  bool is_string() const;
  bool is_number() const;
  bool is_integer() const;  // a number written without fraction or exponent
  bool is_boolean() const;

  // --- Objects.  Each fails "expected a JSON object, found T" on another type.
  // Schema error naming the first key (in file order) not in `allowed`.
  const JsonValue& only_keys(std::initializer_list<std::string_view> allowed) const;
  const JsonValue& only_keys(const std::vector<std::string_view>& allowed) const;
  bool has(std::string_view key) const;
  JsonValue at(std::string_view key) const;  // "PATH.key: missing required key"
  std::optional<JsonValue> find(std::string_view key) const;
  std::vector<std::pair<std::string, JsonValue>> members() const;  // in file order

  // --- Arrays.  Each fails "expected an array, found T" on another type.
  std::size_t size() const;
  std::vector<JsonValue> elements() const;
  // An array of exactly n elements, else "expected an array of N numbers"
  // (`what` names the elements).
  std::vector<JsonValue> elements(std::size_t n, std::string_view what) const;

  // --- Scalars.
  double number() const;                // a finite number (integers too)
  std::vector<double> numbers() const;  // an array of finite numbers
  long long integer() const;            // a number without fraction or exponent
  // An integer in [lo, hi]; outside: Schema "expected a whole number in
  // [lo, hi]" (`what` replaces "a whole number" when given).
  long long integer(long long lo, long long hi, std::string_view what = {}) const;
  std::uint64_t count() const;  // a non-negative integer
  std::string string() const;
  bool boolean() const;

  // A string from a list of names: `names` pairs each name with its value;
  // another string fails "must be \"a\", \"b\" or \"c\", not \"d\"".
  template <class E>
  E choice(std::initializer_list<std::pair<std::string_view, E>> names) const {
    const std::string s = string();
    for (const auto& [name, value] : names)
      if (s == name) return value;
    std::vector<std::string_view> list;
    for (const auto& n : names) list.push_back(n.first);
    fail(must_be(list) + ", not \"" + s + "\"");
  }
  // A string converted by `from_string` (returning std::optional<E>, as the
  // settings' *_from_string functions do); one it refuses fails "must be
  // EXPECTED, not \"d\"" (EXPECTED e.g. "\"standard\" or \"reversed\"").
  template <class F>
  auto parsed(F from_string, std::string_view expected) const -> typename decltype(from_string(""))::value_type {
    if (!is_string()) fail("must be " + std::string(expected) + ", found " + type_name());
    const auto v = from_string(string());
    if (!v) fail("must be " + std::string(expected) + ", not \"" + string() + "\"");
    return *v;
  }

  // Typed access by key: T is double, long long, std::uint64_t, std::string,
  // bool or JsonValue.
  template <class T>
  T get() const;
  template <class T>
  T required(std::string_view key) const {
    return at(key).get<T>();
  }
  template <class T>
  std::optional<T> optional(std::string_view key) const {
    const auto v = find(key);
    if (!v) return std::nullopt;
    return v->get<T>();
  }

  // This value as compact JSON text (object keys sorted).
  std::string dump() const;

  // "\"a\", \"b\" or \"c\"" from a list of names.
  static std::string must_be(const std::vector<std::string_view>& names);

 private:
  friend class JsonDocument;
  friend JsonValue json_value(std::shared_ptr<const JsonTree>, const void*, std::string);
  JsonValue(std::shared_ptr<const JsonTree> tree, const void* node, std::string path)
      : tree_(std::move(tree)), node_(node), path_(std::move(path)) {}
  JsonValue child(std::string_view key, const void* node) const;
  JsonValue element(std::size_t index, const void* node) const;
  void expect_object() const;
  void expect_array() const;

  std::shared_ptr<const JsonTree> tree_;
  const void* node_;  // a node of tree_'s document (src/io/json_tree.hpp)
  std::string path_;  // "" for the root
};

template <>
double JsonValue::get<double>() const;
template <>
long long JsonValue::get<long long>() const;
template <>
std::uint64_t JsonValue::get<std::uint64_t>() const;
template <>
std::string JsonValue::get<std::string>() const;
template <>
bool JsonValue::get<bool>() const;
template <>
JsonValue JsonValue::get<JsonValue>() const;

class JsonDocument {
 public:
  // Parses `text` (`source` names it in messages).  Errors: Parse (not JSON,
  // a number beyond double's range: the message has the path of the value
  // being read, and the line and column for syntax), Schema (a duplicate key).
  static JsonDocument parse(const std::string& text, const std::string& source);

  JsonValue root() const;

 private:
  explicit JsonDocument(std::shared_ptr<const JsonTree> tree) : tree_(std::move(tree)) {}
  std::shared_ptr<const JsonTree> tree_;
};

}  // namespace nearcap::io
