#include "hdvio/core/config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hdvio/core/error.h"

namespace hdvio {
namespace {
using ::testing::HasSubstr;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ReadsTypedValuesAndDefaults) {
  auto cfg = ConfigReader::fromString("rate: 200\nname: circle\nwind:\n  speed: [1, 2, 3]\n", "x.yaml");
  int rate = 0;
  std::string name;
  double missing = 7.5;
  cfg.read("rate", &rate);
  cfg.read("name", &name);
  cfg.readOptional("missing", &missing);
  auto wind = cfg.section("wind");
  std::vector<double> speed;
  wind.read("speed", &speed);
  wind.finish();
  cfg.finish();
  EXPECT_EQ(rate, 200);
  EXPECT_EQ(name, "circle");
  EXPECT_DOUBLE_EQ(missing, 7.5);
  EXPECT_EQ(speed, (std::vector<double>{1, 2, 3}));
  const std::string eff = cfg.effectiveYaml();
  EXPECT_THAT(eff, HasSubstr("missing: 7.5"));
  EXPECT_THAT(eff, HasSubstr("rate: 200"));
}

TEST(Config, UnknownKeyNamesFileLineAndPath) {
  auto cfg = ConfigReader::fromString("a: 1\nsub:\n  b: 2\n  typo: 3\n", "exp.yaml");
  int a = 0, b = 0;
  cfg.read("a", &a);
  auto sub = cfg.section("sub");
  sub.read("b", &b);
  EXPECT_EQ(errorOf([&] { sub.finish(); }), "exp.yaml:4: key 'sub.typo': unknown key");
}

// A problem a program finds in a value names the key's line, or the map's for an absent key.
TEST(Config, FailNamesTheKeysLineOrTheMaps) {
  auto cfg = ConfigReader::fromString("a: 1\nsub:\n  b: 2\n  c: 3\n", "exp.yaml");
  const ConfigReader sub = cfg.section("sub");
  EXPECT_EQ(errorOf([&] { sub.fail("c", "too large"); }), "exp.yaml:4: key 'sub.c': too large");
  EXPECT_EQ(errorOf([&] { sub.fail("d", "missing"); }), "exp.yaml:3: key 'sub.d': missing");
}

TEST(Config, RootFinishChecksOpenedSectionsAndListItems) {
  auto cfg = ConfigReader::fromString(
      "a: 1\nsub:\n  b: 2\n  deeper:\n    typo: 3\n", "exp.yaml");
  int a = 0, b = 0, c = 0;
  cfg.read("a", &a);
  auto sub = cfg.section("sub");
  sub.read("b", &b);
  sub.section("deeper");  // opened, nothing read: its typo must still be found
  EXPECT_EQ(errorOf([&] { cfg.finish(); }), "exp.yaml:5: key 'sub.deeper.typo': unknown key");

  auto cfg2 = ConfigReader::fromString("items:\n  - {c: 1}\n  - {c: 2, bad: 0}\n", "l.yaml");
  for (auto& item : cfg2.list("items")) item.read("c", &c);
  EXPECT_EQ(errorOf([&] { cfg2.finish(); }), "l.yaml:3: key 'items[1].bad': unknown key");
}

TEST(Config, WrongTypeAndRangeAndChoiceAreErrors) {
  auto cfg = ConfigReader::fromString("n: 1.5\nflag: maybe\nx: 12\nmode: fast\n", "c.yaml");
  int n = 0;
  bool flag = false;
  double x = 0;
  std::string mode;
  EXPECT_EQ(errorOf([&] { cfg.read("n", &n); }), "c.yaml:1: key 'n': expected an integer");
  EXPECT_EQ(errorOf([&] { cfg.read("flag", &flag); }),
            "c.yaml:2: key 'flag': expected a boolean (true/false)");
  EXPECT_THAT(errorOf([&] { cfg.readInRange("x", &x, 0.0, 10.0, true); }),
              HasSubstr("c.yaml:3: key 'x': value 12 out of range [0, 10]"));
  EXPECT_THAT(errorOf([&] { cfg.readChoice("mode", &mode, {"vio", "hdvio"}); }),
              HasSubstr("'fast' is not one of: vio, hdvio"));
  EXPECT_THAT(errorOf([&] { cfg.read("absent", &x); }), HasSubstr("required key is missing"));
}

TEST(Config, EnumsAreReadByNameAndWrittenByName) {
  enum class Loss { kNone, kHuber, kCauchy };
  const std::vector<std::pair<std::string, Loss>> names{
      {"none", Loss::kNone}, {"huber", Loss::kHuber}, {"cauchy", Loss::kCauchy}};
  auto cfg = ConfigReader::fromString("loss: cauchy\nbad: fast\n", "e.yaml");
  Loss loss = Loss::kHuber, other = Loss::kNone, bad = Loss::kNone;
  cfg.readEnum("loss", &loss, names);
  EXPECT_EQ(loss, Loss::kCauchy);
  cfg.readEnum("absent", &other, names);  // the default stays and is written by its name
  EXPECT_EQ(other, Loss::kNone);
  EXPECT_THAT(cfg.effectiveYaml(), HasSubstr("absent: none"));
  EXPECT_THAT(errorOf([&] { cfg.readEnum("bad", &bad, names); }),
              HasSubstr("e.yaml:2: key 'bad': 'fast' is not one of: none, huber, cauchy"));
}

TEST(Config, RepeatedKeysAreErrors) {
  EXPECT_EQ(errorOf([] { ConfigReader::fromString("a: 1\nsub:\n  b: 2\n  b: 3\n", "d.yaml"); }),
            "d.yaml:4: key 'b' repeats the one on line 3");
  EXPECT_EQ(errorOf([] { ConfigReader::fromString("a: 1\na: 2\n", "d.yaml"); }),
            "d.yaml:2: key 'a' repeats the one on line 1");
}

TEST(Config, ListsOfMapsAndParseErrors) {
  auto cfg = ConfigReader::fromString("events:\n  - {t: 1.0}\n  - {t: 2.0, bad: 1}\n", "l.yaml");
  auto events = cfg.list("events");
  ASSERT_EQ(events.size(), 2u);
  double t = 0;
  events[1].read("t", &t);
  EXPECT_EQ(errorOf([&] { events[1].finish(); }), "l.yaml:3: key 'events[1].bad': unknown key");
  EXPECT_THAT(errorOf([] { ConfigReader::fromString("a: [1, 2\n", "p.yaml"); }),
              HasSubstr("p.yaml:"));
  EXPECT_THAT(errorOf([] { ConfigReader::fromFile("/nonexistent/x.yaml"); }),
              HasSubstr("cannot open config file"));
}

}  // namespace
}  // namespace hdvio
