// The strict TOML table reader every user file goes through (scenarios, sweeps, calibration targets):
// what it reads comes back typed and checked, and whatever it neither read nor was told to allow is
// refused, naming the file, the field's dotted path, and what the table may hold.

#include "sim/core/toml_table.h"
#include "sim/core/input_error.h"
#include "sim/core/toml_file.h"
#include "tests/support/input_errors.h"

#include <gtest/gtest.h>

#include <string>

namespace pp5 {
namespace {

TEST(TomlTable, ReadsTypedValuesAndRefusesWhatItNeitherReadNorAllowed) {
    const toml::table root = read_toml_text(
        "title = 'x'\nsize = 3\n[image]\nwidth = 4\nwidht = 5\n[[rows]]\nname = 'a'\n[[rows]]\nname = 'b'\nnmae = "
        "'c'\n",
        "file.toml");
    TomlTable top(&root, "", "file.toml", "see the manual");
    EXPECT_EQ(top.text("title"), "x");
    EXPECT_EQ(top.integer("size", 1, 10), 3);
    EXPECT_FALSE(top.number("absent", 0, 1).has_value());
    TomlTable image = top.sub("image");
    EXPECT_EQ(image.integer("width", 1, 100), 4);
    image.allow({"height"});
    const InputError misspelt = test::input_error_from([&] { image.finish(); });
    EXPECT_EQ(misspelt.file(), "file.toml");
    EXPECT_EQ(misspelt.field(), "image.widht");
    EXPECT_EQ(misspelt.reason(), "unknown field; image has width and height (see the manual)");

    std::vector<std::string> names;
    const InputError row = test::input_error_from(
        [&] { top.table_array("rows", [&](TomlTable& r) { names.push_back(r.required_text("name")); }); });
    EXPECT_EQ(names, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(row.field(), "rows[1].nmae");
    top.allow({"image"});
    top.finish();  // title, size, absent, image and rows were all read
}

TEST(TomlTable, RefusesWrongTypesAndValuesOutOfRangeNamingTheField) {
    const toml::table root =
        read_toml_text("n = 'three'\nbig = 11\nnan = nan\nv = [1, 2]\nlist = ['a', 1]\nflag = 1\nt = 3\n", "f.toml");
    TomlTable top(&root, "", "f.toml");
    EXPECT_EQ(test::input_error_from([&] { top.integer("n", 0, 10); }).reason(), "expected an integer");
    EXPECT_EQ(test::input_error_from([&] { top.integer("big", 0, 10); }).reason(),
              "11 is outside the allowed range [0, 10]");
    EXPECT_EQ(test::input_error_from([&] { top.number("nan", 0, 10); }).reason(), "must be a finite number");
    EXPECT_EQ(test::input_error_from([&] { top.triple("v", 0, 10); }).reason(), "expected an array of three numbers");
    EXPECT_EQ(test::input_error_from([&] { top.text_list("list"); }).field(), "list");
    EXPECT_EQ(test::input_error_from([&] { top.boolean("flag"); }).reason(), "expected true or false");
    EXPECT_EQ(test::input_error_from([&] { top.sub("t"); }).reason(), "expected a table");
    EXPECT_EQ(test::input_error_from([&] { top.required_text("missing"); }).reason(), "is missing");
}

}  // namespace
}  // namespace pp5
