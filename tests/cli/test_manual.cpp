// The manual tells the truth: every option of every command is in its --help and its man
// page, and fvx.1 names every command.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "cli_support.hpp"
#include "command_table.hpp"

namespace fvx::test {
namespace {

/// A man page with roff escapes removed ("\-\-max\-range" → "--max-range", fonts dropped).
std::string man_page_text(const std::string& name) {
  const char* source = std::getenv("FVX_SOURCE_DIR");
  EXPECT_NE(source, nullptr) << "FVX_SOURCE_DIR is set by CTest";
  std::string text = slurp(std::string(source ? source : ".") + "/man/" + name);
  for (const char* font : {"\\fB", "\\fI", "\\fR", "\\fP"}) {
    for (auto at = text.find(font); at != std::string::npos; at = text.find(font)) text.erase(at, 3);
  }
  for (auto at = text.find("\\-"); at != std::string::npos; at = text.find("\\-")) text.erase(at, 1);
  return text;
}

TEST(Manual, EveryOptionIsInHelpAndManPage) {
  for (const cli::Command& command : cli::commands()) {
    const std::string page = man_page_text(std::string("fvx-") + command.spec.name + ".1");
    ASSERT_FALSE(page.empty()) << "man/fvx-" << command.spec.name << ".1 is missing";
    const std::string help = cli::help_text(command.spec);
    for (const cli::OptionSpec& option : command.spec.options) {
      const std::string flag = std::string("--") + option.name;
      EXPECT_NE(help.find(flag), std::string::npos) << command.spec.name << " --help lacks " << flag;
      EXPECT_NE(page.find(flag), std::string::npos) << "fvx-" << command.spec.name << ".1 lacks " << flag;
    }
  }
}

/// The paragraph of `flag` in a man page: from the .TP item whose tag names it to the next
/// item or section; empty when there is none.
std::string option_paragraph(const std::string& page, const std::string& flag) {
  for (std::size_t at = page.find(".TP\n"); at != std::string::npos; at = page.find(".TP\n", at + 1)) {
    const std::size_t tag_end = page.find('\n', at + 4);
    const std::string tag = page.substr(at + 4, tag_end - at - 4);
    const std::size_t name = tag.find(flag);
    if (name == std::string::npos || std::isalnum(static_cast<unsigned char>(tag[name + flag.size()])) ||
        tag[name + flag.size()] == '-')
      continue;
    std::size_t end = std::min(page.find("\n.TP\n", tag_end), page.find("\n.SH", tag_end));
    return page.substr(tag_end, end == std::string::npos ? std::string::npos : end - tag_end);
  }
  return "";
}

TEST(Manual, EveryDeclaredDefaultIsTheManPagesDefault) {
  for (const cli::Command& command : cli::commands()) {
    const std::string page = man_page_text(std::string("fvx-") + command.spec.name + ".1");
    for (const cli::OptionSpec& option : command.spec.options) {
      if (option.default_text.empty()) continue;
      const std::string value = option.default_text.substr(0, option.default_text.find_first_of(":;, "));
      const std::string flag = std::string("--") + option.name;
      std::string paragraph = option_paragraph(page, flag);  // "Default 10." or "(default 10)"
      std::transform(paragraph.begin(), paragraph.end(), paragraph.begin(), [](char c) { return std::tolower(c); });
      EXPECT_NE(paragraph.find("default " + value), std::string::npos)
          << "fvx-" << command.spec.name << ".1: " << flag << " should say 'default " << value << "':" << paragraph;
      const std::string help = cli::help_text(command.spec);
      const std::string range = option.range ? "; range " + range_text(*option.range) : "";
      EXPECT_NE(help.find("(default " + option.default_text + range + ")"), std::string::npos) << flag;
    }
  }
}

// --help shows the values each numeric option accepts, as an interval that says which ends
// are open; the checks of parsing refuse what lies outside it.
TEST(Manual, HelpShowsEveryDeclaredRange) {
  EXPECT_EQ(range_text(in(1, 1024)), "[1, 1024]");
  EXPECT_EQ(range_text(above(0, 10)), "(0, 10]");
  EXPECT_EQ(range_text(above(0)), "(0, inf)");
  EXPECT_EQ(range_text(in(0.5, 2.25)), "[0.5, 2.25]");
  EXPECT_EQ(range_text(in(0, double(std::numeric_limits<long long>::max()))), "[0, 2^63-1]");
  std::size_t ranged = 0;
  for (const cli::Command& command : cli::commands()) {
    const std::string help = cli::help_text(command.spec);
    for (const cli::OptionSpec& option : command.spec.options) {
      if (!option.range) continue;
      ++ranged;
      EXPECT_NE(help.find("range " + range_text(*option.range) + ")"), std::string::npos)
          << command.spec.name << " --" << option.name;
    }
  }
  EXPECT_GT(ranged, 50u);  // every numeric option declares its range
}

TEST(Manual, EveryCommandHasHelp) {
  for (const cli::Command& command : cli::commands()) {
    bool has_help = false;
    for (const cli::OptionSpec& option : command.spec.options) has_help |= std::string(option.name) == "help";
    EXPECT_TRUE(has_help) << command.spec.name << " has no --help in its option table";
  }
}

TEST(Manual, FvxPageNamesEveryCommandInTableOrder) {
  const std::string page = man_page_text("fvx.1");
  std::size_t last = 0;
  for (const cli::Command& command : cli::commands()) {
    const std::size_t at = page.find(std::string("fvx-") + command.spec.name);
    ASSERT_NE(at, std::string::npos) << "fvx.1 lacks " << command.spec.name;
    EXPECT_GE(at, last) << "fvx.1 lists " << command.spec.name << " out of pipeline order";
    last = at;
  }
}

TEST(Manual, HelpListsCommandsInTableOrder) {
  const std::string help = cli::top_level_help();
  std::size_t last = 0;
  for (const cli::Command& command : cli::commands()) {
    const std::size_t at = help.find(std::string("  ") + command.spec.name + " ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_GE(at, last);
    last = at;
  }
}

}  // namespace
}  // namespace fvx::test
