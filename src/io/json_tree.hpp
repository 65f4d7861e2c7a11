// The parsed document behind io::JsonValue (include/nearcap/io/json_reader.hpp),
// and a way to make a JsonValue from a document built in memory (the tests
// use it for what JSON text cannot spell: an infinite number).
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

#include "nearcap/io/json_reader.hpp"

namespace nearcap::io {

// Ordered: members() and only_keys() meet keys in the order the file has them.
using JsonNode = nlohmann::ordered_json;

struct JsonTree {
  JsonNode root;
  std::string source;
};

// The root of `root` as a JsonValue naming `source`.
JsonValue json_value(std::shared_ptr<const JsonTree> tree, const void* node, std::string path);
JsonValue json_root(JsonNode root, std::string source);

}  // namespace nearcap::io
