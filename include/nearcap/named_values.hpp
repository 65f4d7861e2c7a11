// nearcap/named_values.hpp — one table per named choice: each value of an
// enum, the name files and the command line spell it with, and a one-line
// description.
//
// A choice (a shadow method, a light projection, a far-plane mode, ...) is
// spelled once, in a constexpr table next to its enum:
//
//   enum class ZPassFar { Finite, Infinite };
//   inline constexpr NamedValue<ZPassFar> kZPassFarTable[] = {
//       {ZPassFar::Finite, "finite", "its own frustum"},
//       {ZPassFar::Infinite, "infinite", "the infinite far plane"}};
//   constexpr const auto& named_values(ZPassFar) { return kZPassFarTable; }
//
// and everything that names the values reads that table: to_string and the
// *_from_string parsers, the "expected one of ..." lists of errors, the
// command line's accepted values and help, the sweep's CSV and the JSON
// files.  `named_values(E)` is found by argument-dependent lookup in the
// enum's namespace, so the functions below take the enum type alone.
//
// Names are case-sensitive and matched whole.  The table's order is the
// order lists are printed in; a value may appear once only, and so may a
// name.
#pragma once

#include <array>
#include <cstddef>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nearcap {

template <class E>
struct NamedValue {
  E value;
  std::string_view name;  // the spelling in files and on the command line
  std::string_view help;  // a short description for help texts; empty when the name says it all
};

// The table of E (its `named_values(E)`).
template <class E>
constexpr const auto& table_of() {
  return named_values(E{});
}

// The number of named values of E.
template <class E>
constexpr std::size_t named_count() {
  return std::size(table_of<E>());
}

// The values, in the table's order.
template <class E>
constexpr std::array<E, named_count<E>()> values_of() {
  std::array<E, named_count<E>()> values{};
  for (std::size_t k = 0; k < values.size(); ++k) values[k] = table_of<E>()[k].value;
  return values;
}

// The name of `value`; "?" for a value outside the table.
template <class E>
constexpr std::string_view name_of(E value) {
  for (const NamedValue<E>& v : table_of<E>())
    if (v.value == value) return v.name;
  return "?";
}

// The value called `name`; nullopt when no value has that name.
template <class E>
constexpr std::optional<E> value_named(std::string_view name) {
  for (const NamedValue<E>& v : table_of<E>())
    if (v.name == name) return v.value;
  return std::nullopt;
}

// The table's names, in its order.
template <class E>
std::vector<std::string> names_of() {
  std::vector<std::string> names;
  for (const NamedValue<E>& v : table_of<E>()) names.emplace_back(v.name);
  return names;
}

// The names joined: "a, b, c" (last = ", "), or "a, b or c" (last = " or ").
template <class E>
std::string names_joined(std::string_view last = ", ") {
  std::string list;
  const auto& table = table_of<E>();
  for (std::size_t k = 0; k < std::size(table); ++k) {
    if (k > 0) list += k + 1 == std::size(table) ? last : std::string_view(", ");
    list += table[k].name;
  }
  return list;
}

// The names with their descriptions, for a help text:
// "a, b (what b does) or c (what c does)" (last = " or "); a value with no
// description is its name alone.
template <class E>
std::string values_described(std::string_view last = " or ") {
  std::string list;
  const auto& table = table_of<E>();
  for (std::size_t k = 0; k < std::size(table); ++k) {
    if (k > 0) list += k + 1 == std::size(table) ? last : std::string_view(", ");
    list += table[k].name;
    if (!table[k].help.empty()) {
      list += " (";
      list += table[k].help;
      list += ")";
    }
  }
  return list;
}

// True when no value and no name appears twice in E's table (each table
// states it with a static_assert).
template <class E>
constexpr bool names_are_unique() {
  const auto& table = table_of<E>();
  for (std::size_t i = 0; i < std::size(table); ++i)
    for (std::size_t j = i + 1; j < std::size(table); ++j)
      if (table[i].value == table[j].value || table[i].name == table[j].name) return false;
  return true;
}

}  // namespace nearcap
