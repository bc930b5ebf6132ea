#include "pliant/core/json_reader.h"

#include <gtest/gtest.h>

#include "input_error_of.h"

namespace pliant {
namespace {

using nlohmann::json;

using test::error_of;

const json kDoc = json::parse(R"({
  "grid": {"resolution": [-3, 4], "resoluton": [1, 2], "cell_size_m": 0.01, "boundary": "perodic"},
  "time": {"frames": 2.5, "substeps": "3", "count": 3.0, "flag": 1, "title": true, "big": 100},
  "sources": [{"radius_m": 0.1}, {"radius_m": -1}],
  "a/b~c": 1
})");

TEST(JsonReader, InputErrorFormat) {
  InputError e("scenes/a.json", "/grid", "bad");
  EXPECT_STREQ(e.what(), "scenes/a.json: /grid: bad");
  EXPECT_STREQ(InputError("a.json", "", "bad").what(), "a.json: bad");
  EXPECT_EQ(e.file(), "scenes/a.json");
  EXPECT_EQ(e.pointer(), "/grid");
  EXPECT_EQ(e.problem(), "bad");
}

TEST(JsonReader, PositiveIntegerElementNamesItsPointer) {
  JsonReader root(kDoc, "scenes/a.json");
  auto grid = root.object("grid");
  ASSERT_TRUE(grid);
  EXPECT_EQ(error_of([&] { grid->integers("resolution", {}, 2, 3, 1); }),
            "scenes/a.json: /grid/resolution/0: expected a positive integer, got -3");
}

TEST(JsonReader, UnknownFieldSuggestsNearest) {
  JsonReader root(kDoc, "scenes/a.json");
  auto grid = root.object("grid");
  grid->accept("resolution");
  grid->number("cell_size_m", 0.02);
  grid->string("boundary", "closed");
  EXPECT_EQ(error_of([&] { grid->finish(); }),
            "scenes/a.json: /grid/resoluton: unknown field; did you mean \"resolution\"?");
  grid->accept("resoluton");
  EXPECT_EQ(error_of([&] { grid->finish(); }), "");
}

TEST(JsonReader, UnknownFieldWithoutNearName) {
  json doc = {{"zzzzzzzz", 1}, {"alpha", 2}};
  JsonReader r(doc, "a.json");
  r.number("alpha", 0);
  EXPECT_EQ(error_of([&] { r.finish(); }), "a.json: /zzzzzzzz: unknown field");
}

TEST(JsonReader, IntegersRejectFractionsAndStrings) {
  JsonReader root(kDoc, "a.json");
  auto time = root.object("time");
  EXPECT_EQ(error_of([&] { time->integer("frames", 1); }), "a.json: /time/frames: expected an integer, got 2.5");
  EXPECT_EQ(error_of([&] { time->integer("substeps", 1); }),
            "a.json: /time/substeps: expected an integer, got \"3\"");
  EXPECT_EQ(time->integer("count", 1), 3);  // 3.0 is an integer written as a float
  EXPECT_EQ(error_of([&] { time->integer("big", 1, 1, 64); }),
            "a.json: /time/big: expected an integer in [1, 64], got 100");
  EXPECT_EQ(error_of([&] { time->integer("big", 1, 0, 10); }),
            "a.json: /time/big: expected an integer in [0, 10], got 100");
  EXPECT_EQ(time->integer("absent", 7), 7);
}

TEST(JsonReader, WrongTypesQuoteTheValueAsJson) {
  JsonReader root(kDoc, "a.json");
  auto time = root.object("time");
  EXPECT_EQ(error_of([&] { time->number("substeps", 1); }),
            "a.json: /time/substeps: expected a number, got \"3\"");
  EXPECT_EQ(error_of([&] { time->boolean("flag", false); }),
            "a.json: /time/flag: expected true or false, got 1");
  EXPECT_EQ(error_of([&] { time->string("title", ""); }), "a.json: /time/title: expected a string, got true");
  EXPECT_EQ(error_of([&] { root.object("sources"); }), "a.json: /sources: expected an object, got an array of 2");
  EXPECT_EQ(error_of([&] { JsonReader(json(3), "a.json", "/x"); }), "a.json: /x: expected an object, got 3");
}

TEST(JsonReader, NumberBounds) {
  JsonReader root(kDoc, "a.json");
  auto grid = root.object("grid");
  EXPECT_DOUBLE_EQ(grid->number("cell_size_m", 1, 0, 1), 0.01);
  EXPECT_EQ(error_of([&] { grid->number("cell_size_m", 1, 0.5, 1); }),
            "a.json: /grid/cell_size_m: expected a number in [0.5, 1], got 0.01");
  EXPECT_EQ(error_of([&] { grid->number("cell_size_m", 1, 0.5); }),
            "a.json: /grid/cell_size_m: expected a number >= 0.5, got 0.01");
  EXPECT_EQ(error_of([&] { grid->number("cell_size_m", 1, -1e300, 0.001); }),
            "a.json: /grid/cell_size_m: expected a number <= 0.001, got 0.01");
}

TEST(JsonReader, MissingRequired) {
  JsonReader root(kDoc, "a.json");
  auto time = root.object("time");
  EXPECT_EQ(error_of([&] { time->required_number("dt_s"); }),
            "a.json: /time/dt_s: missing required field; expected a number");
  EXPECT_EQ(error_of([&] { time->required_integer("n"); }),
            "a.json: /time/n: missing required field; expected an integer");
  EXPECT_EQ(error_of([&] { time->required_string("s"); }),
            "a.json: /time/s: missing required field; expected a string");
}

TEST(JsonReader, ChoiceListsAllowedAndSuggests) {
  JsonReader root(kDoc, "a.json");
  auto grid = root.object("grid");
  EXPECT_EQ(error_of([&] { grid->choice("boundary", "closed", {"closed", "periodic"}); }),
            "a.json: /grid/boundary: expected one of \"closed\", \"periodic\", got \"perodic\"; "
            "did you mean \"periodic\"?");
  EXPECT_EQ(grid->choice("absent", "closed", {"closed", "periodic"}), "closed");
}

TEST(JsonReader, ArraysCheckSizeAndElements) {
  json doc = json::parse(R"({"c": [0.5, 0.25], "v": [1, "x", 3], "n": 4})");
  JsonReader r(doc, "a.json");
  EXPECT_EQ(r.numbers("c", {}, 2, 3), (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(error_of([&] { r.numbers("c", {}, 3, 3); }),
            "a.json: /c: expected an array of 3 numbers, got an array of 2");
  EXPECT_EQ(error_of([&] { r.numbers("n", {}, 2, 3); }), "a.json: /n: expected an array of 2 to 3 numbers, got 4");
  EXPECT_EQ(error_of([&] { r.numbers("v", {}, 3, 3); }), "a.json: /v/1: expected a number, got \"x\"");
  EXPECT_EQ(error_of([&] { r.integers("c", {}, 2, 2); }), "a.json: /c/0: expected an integer, got 0.5");
  EXPECT_EQ(r.numbers("absent", {1, 2, 3}, 3, 3), (std::vector<double>{1, 2, 3}));
}

TEST(JsonReader, ObjectsCarryElementPointers) {
  JsonReader root(kDoc, "a.json");
  auto sources = root.objects("sources");
  ASSERT_EQ(sources.size(), 2u);
  EXPECT_DOUBLE_EQ(sources[0].number("radius_m", 0, 0), 0.1);
  EXPECT_EQ(error_of([&] { sources[1].number("radius_m", 0, 0); }),
            "a.json: /sources/1/radius_m: expected a non-negative number, got -1");
  EXPECT_TRUE(root.objects("absent").empty());
  EXPECT_EQ(error_of([&] { root.objects("grid"); }), "a.json: /grid: expected an array of objects, got an object");
}

TEST(JsonReader, PointerEscapesTildeAndSlash) {
  JsonReader root(kDoc, "a.json");
  EXPECT_EQ(root.child_pointer("a/b~c"), "/a~1b~0c");
  EXPECT_EQ(error_of([&] { root.string("a/b~c", ""); }), "a.json: /a~1b~0c: expected a string, got 1");
}

TEST(EditDistance, Levenshtein) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("abc", "abc"), 0u);
  EXPECT_EQ(edit_distance("resoluton", "resolution"), 1u);
  EXPECT_EQ(nearest_name("smok", {"smoke", "liquid", "soft"}), "smoke");
  EXPECT_EQ(nearest_name("xyzzy", {"smoke", "liquid", "soft"}), "");
  // Two edits away is still close.
  EXPECT_EQ(nearest_name("artculatd", {"articulated"}), "articulated");
}

}  // namespace
}  // namespace pliant
