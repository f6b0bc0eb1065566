#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <set>

#include "io/class_table_io.h"
#include "test_data.h"

namespace vf {
namespace {

using test::errorOf;


TEST(ClassTableIo, ListForm) {
  const ClassTable t = parseClassTable(R"([{"id": 3, "name": "chair", "color": [10, 20, 30]},
                                            {"id": 0, "name": "wall"}])", "test");
  ASSERT_EQ(t.classes.size(), 2u);
  EXPECT_EQ(t.classes[0].id, 0);  // sorted by id
  EXPECT_EQ(t.classes[1].name, "chair");
  EXPECT_EQ(t.classes[1].color.g, 20);
  EXPECT_EQ(t.classes[0].color.r, paletteColor(0).r);
}

TEST(ClassTableIo, DanceLabelsClassesJsonLoads) {
  VF_REQUIRE_DATA(path, "record3d_dance_head200_labels/classes.json");
  const ClassTable t = readClassTable(path);
  ASSERT_EQ(t.classes.size(), 2u);
  EXPECT_EQ(t.findId(0)->name, "background");
  EXPECT_EQ(t.findId(1)->name, "person");
  EXPECT_EQ(t.findName("person")->id, 1);
  // Palette colours: 0 black, 1 dark red (PASCAL VOC colour map).
  EXPECT_EQ(t.findId(1)->color.r, 128);
  EXPECT_EQ(t.findId(1)->color.g, 0);
  EXPECT_EQ(t.findId(1)->color.b, 0);
}

TEST(ClassTableIo, PaletteIsDistinct) {
  std::set<int> seen;
  for (int id = 0; id < 4096; ++id) {
    const Rgb8 c = paletteColor(id);
    seen.insert(c.r << 16 | c.g << 8 | c.b);
  }
  EXPECT_EQ(seen.size(), 4096u);
  EXPECT_EQ(paletteColor(15).r, 192);  // VOC id 15 "person" is (192, 128, 128)
  EXPECT_EQ(paletteColor(15).g, 128);
  EXPECT_EQ(paletteColor(15).b, 128);
}

TEST(ClassTableIo, ErrorsNameTheFileAndProblem) {
  const std::string dir = test::tempDir("class_table_errors");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const std::string dup_id = write("dup_id.json", R"([{"id":1,"name":"a"},{"id":1,"name":"b"}])");
  const std::string msg = errorOf([&] { readClassTable(dup_id); });
  EXPECT_NE(msg.find(dup_id), std::string::npos) << msg;
  EXPECT_NE(msg.find("id 1"), std::string::npos) << msg;
  const std::string dup_name = write("dup_name.json", R"({"0":"a","1":"a"})");
  EXPECT_NE(errorOf([&] { readClassTable(dup_name); }).find("'a' appears twice"), std::string::npos);
  const std::string dup_key = write("dup_key.json", R"({"0":"a","0":"b"})");
  EXPECT_NE(errorOf([&] { readClassTable(dup_key); }).find("appears twice"), std::string::npos);
  const std::string bad_color = write("bad_color.json", R"([{"id":0,"name":"a","color":[0,300,0]}])");
  EXPECT_NE(errorOf([&] { readClassTable(bad_color); }).find("0..255"), std::string::npos);
  const std::string short_color = write("short_color.json", R"([{"id":0,"name":"a","color":[0,3]}])");
  EXPECT_NE(errorOf([&] { readClassTable(short_color); }).find(short_color), std::string::npos);
  const std::string bad_key = write("bad_key.json", R"({"zero":"a"})");
  EXPECT_NE(errorOf([&] { readClassTable(bad_key); }).find("'zero'"), std::string::npos);
  const std::string not_json = write("not.json", "[{\"id\":0,");
  EXPECT_NE(errorOf([&] { readClassTable(not_json); }).find(not_json), std::string::npos);
  EXPECT_THROW(parseClassTable(R"([{"id":70000,"name":"a"}])", "x"), Error);
  EXPECT_THROW(parseClassTable(R"([{"id":0,"name":""}])", "x"), Error);
  EXPECT_THROW(readClassTable(dir + "/missing.json"), Error);
}

TEST(ClassTableIo, WriteReadRoundTrip) {
  const std::string dir = test::tempDir("class_table_roundtrip");
  ClassTable t;
  t.classes = {{5, "chair \"big\"", {1, 2, 3, 255}}, {0, "wall", {250, 0, 7, 255}}};
  writeClassTable(dir + "/t.json", t);
  const ClassTable back = readClassTable(dir + "/t.json");
  ASSERT_EQ(back.classes.size(), 2u);
  EXPECT_EQ(back.findId(5)->name, "chair \"big\"");
  EXPECT_EQ(back.findId(5)->color.b, 3);
  EXPECT_EQ(back.findId(0)->color.r, 250);
}

TEST(ClassTableSamples, Ade20kHas150SegFormerClasses) {
  const ClassTable t = readClassTable(std::string(VDBFUSE_SOURCE_DIR) + "/samples/classes/ade20k.json");
  ASSERT_EQ(t.classes.size(), 150u);
  EXPECT_EQ(t.classes.front().id, 0);
  EXPECT_EQ(t.classes.back().id, 149);
  EXPECT_EQ(t.findId(0)->name, "wall");
  EXPECT_EQ(t.findId(12)->name, "person");
  EXPECT_EQ(t.findId(19)->name, "chair");
  EXPECT_EQ(t.findId(149)->name, "flag");
  EXPECT_EQ(t.findId(12)->color.r, 150);  // ADE20K palette: person (150, 5, 61)
  EXPECT_EQ(t.findId(12)->color.g, 5);
  EXPECT_EQ(t.findId(12)->color.b, 61);
  EXPECT_EQ(t.findId(149)->color.r, 92);  // flag (92, 0, 255)
}

TEST(ClassTableSamples, CocoStuffAndPerson) {
  const ClassTable coco = readClassTable(std::string(VDBFUSE_SOURCE_DIR) + "/samples/classes/coco_stuff.json");
  ASSERT_EQ(coco.classes.size(), 182u);
  EXPECT_EQ(coco.findId(0)->name, "person");
  EXPECT_EQ(coco.findId(11)->name, "street sign");
  EXPECT_EQ(coco.findId(90)->name, "hair brush");
  EXPECT_EQ(coco.findId(91)->name, "banner");
  EXPECT_EQ(coco.findId(181)->name, "wood");
  const ClassTable person = readClassTable(std::string(VDBFUSE_SOURCE_DIR) + "/samples/classes/person.json");
  ASSERT_EQ(person.classes.size(), 2u);
  EXPECT_EQ(person.findName("person")->id, 1);
  EXPECT_EQ(person.findName("background")->id, 0);
}

}  // namespace
}  // namespace vf
