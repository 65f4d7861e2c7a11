// io::JsonDocument / io::JsonValue: each fault of a JSON file is an Error of
// one kind whose message names the file and the JSON path of the value.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "../src/io/json_tree.hpp"
#include "nearcap/error.hpp"
#include "nearcap/io/json_reader.hpp"

namespace nearcap {
namespace {

using io::JsonDocument;
using io::JsonValue;

enum class Colour { Red, Green };

// The one schema the tests read: {"objects": [{"mesh": "a.off", "scale": 2,
// "colour": "red", "hidden": false}], "count": 3}.
void read(const JsonValue& root) {
  root.only_keys({"objects", "count"});
  (void)root.at("count").integer(0, 10);
  for (const JsonValue& o : root.at("objects").elements()) {
    o.only_keys({"mesh", "scale", "colour", "hidden"});
    (void)o.required<std::string>("mesh");
    (void)o.optional<double>("scale");
    if (const auto c = o.find("colour")) (void)c->choice<Colour>({{"red", Colour::Red}, {"green", Colour::Green}});
    (void)o.optional<bool>("hidden");
  }
}

// The Error that reading `text` as "f.json" raises.
Error error_of(const std::string& text) {
  try {
    read(JsonDocument::parse(text, "f.json").root());
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text;
  return Error(ErrorKind::Usage, "");
}

void expect_error(const std::string& text, ErrorKind kind, const std::string& message) {
  const Error e = error_of(text);
  EXPECT_EQ(e.kind(), kind) << e.what();
  EXPECT_EQ(std::string(e.what()), message) << text;
}

const std::string kGood = R"({"count": 3, "objects": [{"mesh": "a.off"}, {"mesh": "b.off", "scale": 2,
  "colour": "green", "hidden": true}]})";

TEST(JsonReader, ReadsAWellFormedFile) {
  const JsonDocument doc = JsonDocument::parse(kGood, "f.json");
  EXPECT_NO_THROW(read(doc.root()));
  const JsonValue second = doc.root().at("objects").elements()[1];
  EXPECT_EQ(second.path(), "objects[1]");
  EXPECT_EQ(second.required<double>("scale"), 2.0);
  EXPECT_EQ(second.at("colour").choice<Colour>({{"red", Colour::Red}, {"green", Colour::Green}}), Colour::Green);
  EXPECT_TRUE(second.required<bool>("hidden"));
  EXPECT_FALSE(doc.root().at("objects").elements()[0].optional<double>("scale"));
  EXPECT_EQ(doc.root().path(), "(top level)");
}

TEST(JsonReader, DuplicateKeyIsASchemaErrorNamingItsPath) {
  expect_error(R"({"count": 3, "objects": [{"mesh": "a.off"}, {"mesh": "b.off", "mesh": "c.off"}]})", ErrorKind::Schema,
               "f.json: objects[1].mesh: duplicate key (each key may appear once in an object)");
  expect_error(R"({"count": 3, "count": 4, "objects": []})", ErrorKind::Schema,
               "f.json: count: duplicate key (each key may appear once in an object)");
  // Equal keys in different objects are not duplicates.
  EXPECT_NO_THROW(
      read(JsonDocument::parse(R"({"count": 1, "objects": [{"mesh": "a"}, {"mesh": "b"}]})", "f.json").root()));
}

TEST(JsonReader, UnknownKeyIsASchemaErrorNamingItAndTheAllowedOnes) {
  expect_error(R"({"count": 3, "objects": [{"mesh": "a.off", "scael": 2}]})", ErrorKind::Schema,
               "f.json: objects[0].scael: unknown key (allowed: mesh, scale, colour, hidden)");
}

TEST(JsonReader, MissingRequiredKeyNamesIt) {
  expect_error(R"({"count": 3, "objects": [{"mesh": "a.off"}, {"scale": 2}]})", ErrorKind::Schema,
               "f.json: objects[1].mesh: missing required key");
  expect_error(R"({"objects": []})", ErrorKind::Schema, "f.json: count: missing required key");
}

TEST(JsonReader, WrongTypeNamesWhatWasExpectedAndFound) {
  expect_error(R"({"count": 3, "objects": [{"mesh": 7}]})", ErrorKind::Schema,
               "f.json: objects[0].mesh: expected a string, found number");
  expect_error(R"({"count": 3, "objects": [{"mesh": "a", "scale": "2"}]})", ErrorKind::Schema,
               "f.json: objects[0].scale: expected a number, found string");
  expect_error(R"({"count": 3, "objects": [{"mesh": "a", "hidden": 0}]})", ErrorKind::Schema,
               "f.json: objects[0].hidden: expected true or false, found number");
  expect_error(R"({"count": 3, "objects": {}})", ErrorKind::Schema, "f.json: objects: expected an array, found object");
  expect_error(R"([])", ErrorKind::Schema, "f.json: (top level): expected a JSON object, found array");
  expect_error(R"({"count": 2.5, "objects": []})", ErrorKind::Schema,
               "f.json: count: expected a whole number in [0, 10], found 2.5");
  expect_error(R"({"count": 11, "objects": []})", ErrorKind::Schema,
               "f.json: count: expected a whole number in [0, 10], found 11");
}

TEST(JsonReader, NameOutsideItsListNamesTheList) {
  expect_error(R"({"count": 3, "objects": [{"mesh": "a", "colour": "blue"}]})", ErrorKind::Schema,
               "f.json: objects[0].colour: must be \"red\" or \"green\", not \"blue\"");
}

TEST(JsonReader, NonFiniteNumberIsANonFiniteError) {
  // JSON text cannot spell infinity: a document built in memory can.
  io::JsonNode root = {{"scale", std::numeric_limits<double>::infinity()}};
  const JsonValue v = io::json_root(std::move(root), "f.json");
  try {
    (void)v.required<double>("scale");
    ADD_FAILURE() << "an infinite scale was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::NonFinite);
    EXPECT_EQ(std::string(e.what()), "f.json: scale: the number is not finite");
  }
}

TEST(JsonReader, NumberBeyondDoubleIsAParseErrorNamingItsPath) {
  const Error e = error_of(R"({"count": 3, "objects": [{"mesh": "a"}, {"mesh": "b", "scale": 1e999}]})");
  EXPECT_EQ(e.kind(), ErrorKind::Parse);
  EXPECT_EQ(std::string(e.what()).rfind("f.json: objects[1].scale: malformed JSON: number overflow", 0), 0u)
      << e.what();
}

TEST(JsonReader, NestingDeeperThan64IsAParseError) {
  // A value nested 100,000 deep and a member after it (the object's member
  // list would copy it recursively as it grows): refused while parsed,
  // naming where.
  const std::size_t deep = 100000;
  const Error e = error_of("{\"objects\": " + std::string(deep, '[') + std::string(deep, ']') + ", \"count\": 3}");
  EXPECT_EQ(e.kind(), ErrorKind::Parse);
  std::string where = "objects";
  for (int k = 0; k < 63; ++k) where += "[0]";
  EXPECT_EQ(std::string(e.what()).rfind("f.json: " + where + ": arrays and objects", 0), 0u) << e.what();
  EXPECT_NE(std::string(e.what()).find("nested more than 64 deep"), std::string::npos) << e.what();
  // 64 levels, the top-level object one of them, are read.
  EXPECT_NO_THROW((void)JsonDocument::parse("{\"a\": " + std::string(63, '[') + std::string(63, ']') + "}", "f.json"));
  EXPECT_THROW((void)JsonDocument::parse("{\"a\": " + std::string(64, '[') + std::string(64, ']') + "}", "f.json"),
               Error);
}

TEST(JsonReader, SyntaxErrorNamesTheLineAndColumn) {
  const Error e = error_of("{\"count\": 3,\n \"objects\": [\n  {\"mesh\": \"a\",}]}");
  EXPECT_EQ(e.kind(), ErrorKind::Parse);
  const std::string m = e.what();
  EXPECT_EQ(m.rfind("f.json: objects[0]: malformed JSON: ", 0), 0u) << m;
  EXPECT_NE(m.find("line 3, column 16"), std::string::npos) << m;
}

TEST(JsonReader, FailNamesTheFileAndThePathForAFilesOwnChecks) {
  const JsonDocument doc = JsonDocument::parse(kGood, "f.json");
  const JsonValue scale = doc.root().at("objects").elements()[1].at("scale");
  try {
    scale.fail(ErrorKind::Range, "must be at most 1");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Range);
    EXPECT_EQ(std::string(e.what()), "f.json: objects[1].scale: must be at most 1");
  }
}

TEST(JsonReader, MembersKeepTheFilesOrderAndDumpSortsKeys) {
  const JsonDocument doc = JsonDocument::parse(R"({"b": 1, "a": {"d": 2, "c": 3}})", "f.json");
  const auto members = doc.root().members();
  ASSERT_EQ(members.size(), 2u);
  EXPECT_EQ(members[0].first, "b");
  EXPECT_EQ(members[1].second.path(), "a");
  EXPECT_EQ(members[1].second.dump(), R"({"c":3,"d":2})");
}

}  // namespace
}  // namespace nearcap
