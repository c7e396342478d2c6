// The option tables (sim/io/option_table.h): flags derived from names as
// docs/CONVENTIONS.md says, messages relocated to flags by whole words,
// defaults taken from the spec, and no two spellings of one flag.
#include "sim/io/option_table.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "sim/optimize/option_reference.h"

namespace ipmc {
namespace {

TEST(OptionTableTest, TheFlagIsTheNameInLowerCaseWithDashes) {
  EXPECT_EQ(OptionFlag("sample_rate_Hz"), "--sample-rate-hz");
  EXPECT_EQ(OptionFlag("v_max_V"), "--v-max-v");
  EXPECT_EQ(OptionFlag("band_rad_s"), "--band-rad-s");
  EXPECT_EQ(OptionFlag("o"), "-o");
}

TEST(OptionTableTest, MessagesGetTheFlagInPlaceOfWholeWords) {
  EXPECT_EQ(WithFlagFor("step: v_max_V must be > 0, got 0 (v_max_V)", "v_max_V"),
            "step: --v-max-v must be > 0, got 0 (--v-max-v)");
  // Not inside a longer name, nor a flag already there.
  EXPECT_EQ(WithFlagFor("start_ramp_cycles in [0, cycles]", "cycles"),
            "start_ramp_cycles in [0, --cycles]");
  EXPECT_EQ(WithFlagFor("--cycles and cycles_2", "cycles"), "--cycles and cycles_2");
}

struct Spec {
  double frequency_Hz = 0.25;
  std::vector<int> links = {1, 3};
  std::string out;
};

TEST(OptionTableTest, DefaultsAreTheSpecsAndTypesTheFields) {
  OptionTable<Spec> table("test", "a test");
  table.Add<double>({"frequency_Hz", "Hz", "> 0", "f"}, [](Spec& s) -> double& {
    return s.frequency_Hz;
  });
  table.Add<std::vector<int>>({"links", "", "1..3", "links"},
                              [](Spec& s) -> std::vector<int>& { return s.links; });
  table.AddPath({"out", "", "a folder", "where"}, [](Spec& s) -> std::string& { return s.out; });
  const std::vector<OptionInfo> infos = table.Infos();
  ASSERT_EQ(infos.size(), 3u);
  EXPECT_EQ(infos[0].default_text, "0.25");
  EXPECT_EQ(infos[0].type, OptionType::kReal);
  EXPECT_EQ(infos[1].default_text, "1,3");
  EXPECT_EQ(infos[1].type, OptionType::kIntegerList);
  EXPECT_EQ(infos[2].type, OptionType::kPath);
  EXPECT_EQ(infos[2].default_text, "");
}

struct Words {
  std::vector<std::string> set = {"cycles=1"};
  std::vector<std::string> formats;
};

// A list of words (run --set) is a type of its own, and an option of the
// command line alone says so in the reference (Python does not read it).
TEST(OptionTableTest, TextListsAndCommandLineOnlyOptions) {
  OptionTable<Words> table("test", "a test");
  OptionInfo set{"set", "", "KEY=VALUE", "a setting"};
  set.command_line_only = true;
  table.Add<std::vector<std::string>>(set, [](Words& w) -> std::vector<std::string>& {
    return w.set;
  });
  table.Add<std::vector<std::string>>({"formats", "", "mat, h5", "files"},
                                      [](Words& w) -> std::vector<std::string>& {
                                        return w.formats;
                                      });
  const std::vector<OptionInfo> infos = table.Infos();
  EXPECT_EQ(infos[0].type, OptionType::kTextList);
  EXPECT_EQ(infos[0].default_text, "cycles=1");
  const std::string reference = OptionReference({InfoOf(table)}, "text");
  EXPECT_NE(reference.find("set (--set) texts, KEY=VALUE, default cycles=1: a setting "
                           "(command line only)"),
            std::string::npos)
      << reference;
  EXPECT_NE(reference.find("formats (--formats) texts, mat, h5, default none: files\n"),
            std::string::npos)
      << reference;
}

TEST(OptionTableTest, TwoSpellingsOfOneFlagAreRefused) {
  OptionTable<Spec> table("test", "a test");
  table.Add<double>({"frequency_Hz", "Hz", "> 0", "f"}, [](Spec& s) -> double& {
    return s.frequency_Hz;
  });
  EXPECT_THROW(table.Add<double>({"frequency_hz", "Hz", "> 0", "f"},
                                 [](Spec& s) -> double& { return s.frequency_Hz; }),
               std::logic_error);
  OptionInfo aliased{"rate_Hz", "Hz", "> 0", "f"};
  aliased.aliases = {"Frequency_Hz"};
  EXPECT_THROW(table.Add<double>(aliased, [](Spec& s) -> double& { return s.frequency_Hz; }),
               std::logic_error);
}

// Every command's table builds (no flag twice) and names its options by
// the convention: lower-case words, with capitals only in a unit suffix.
TEST(OptionTableTest, EveryCommandsTableFollowsTheConvention) {
  const std::vector<OptionTableInfo> tables = EveryOptionTable();
  for (const OptionTableInfo& table : tables) {
    EXPECT_FALSE(table.options.empty()) << table.command;
    for (const OptionInfo& option : table.options) {
      EXPECT_FALSE(option.meaning.empty()) << table.command << " " << option.name;
      const std::string::size_type first_capital = option.name.find_first_of(
          "ABCDEFGHIJKLMNOPQRSTUVWXYZ");
      if (first_capital != std::string::npos) {
        // A capital starts a unit: Hz, V, Pa, N (a unit suffix after '_'),
        // or is the B of a closing dB.
        const bool decibels = option.name.size() > 3 &&
                              option.name.compare(option.name.size() - 3, 3, "_dB") == 0 &&
                              first_capital == option.name.size() - 1;
        EXPECT_TRUE(decibels || option.name[first_capital - 1] == '_')
            << table.command << " " << option.name;
      }
    }
  }
}

}  // namespace
}  // namespace ipmc
