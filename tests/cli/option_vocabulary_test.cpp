// One vocabulary across the commands (cli/shared_options.hpp): the test walks every command's
// --help, so that an option several commands share is spelled, written and parsed the same in
// each, old spellings survive only as deprecated aliases that say so, and the shared options
// accept and refuse the same values everywhere.

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "kincal/cli/cli_util.hpp"
#include "kincal/cli/commands.hpp"

namespace kincal::testing {
namespace {

struct HelpOption {
  std::string spec;         ///< what follows the name: "", "arg", "arg (=1)"
  std::string description;  ///< joined across boost's wrapped lines
};

// "  --name arg (=1)     text..." and its continuation lines, as boost prints them.
std::map<std::string, HelpOption> help_options(const std::string& help) {
  std::map<std::string, HelpOption> options;
  std::istringstream in(help);
  std::string line, current;
  while (std::getline(in, line)) {
    if (line.rfind("  --", 0) == 0) {
      const std::string::size_type name_end = line.find(' ', 4);
      current = line.substr(4, name_end - 4);
      std::string rest = name_end == std::string::npos ? "" : line.substr(name_end);
      const std::string::size_type gap = rest.find("  ", 1);
      const std::string spec = rest.substr(0, gap);
      HelpOption& option = options[current];
      const auto spec_start = spec.find_first_not_of(' ');
      option.spec = spec_start == std::string::npos ? "" : spec.substr(spec_start);
      if (gap != std::string::npos) {
        const auto start = rest.find_first_not_of(' ', gap);
        if (start != std::string::npos) option.description = rest.substr(start);
      }
    } else if (line.rfind("  -", 0) == 0) {
      current.clear();  // "-h [ --help ]"
    } else if (!current.empty() && line.find_first_not_of(' ') != std::string::npos) {
      std::string& text = options[current].description;
      text += (text.empty() ? "" : " ") + line.substr(line.find_first_not_of(' '));
    } else {
      current.clear();
    }
  }
  // Boost wraps at a width that depends on the longest option name: compare words, not lines.
  for (auto& [name, option] : options) {
    std::istringstream words(option.description);
    std::string word, joined;
    while (words >> word) joined += (joined.empty() ? "" : " ") + word;
    option.description = joined;
  }
  return options;
}

// Every command's options, from its --help.
std::map<std::string, std::map<std::string, HelpOption>> every_commands_options() {
  std::map<std::string, std::map<std::string, HelpOption>> all;
  for (const auto& command : cli::commands()) {
    const CliResult help = run_cli(std::string(command.name) + " --help");
    EXPECT_EQ(help.exit_code, 0) << command.name << ": " << help.err;
    all[command.name] = help_options(help.out);
    EXPECT_GT(all[command.name].size(), 1u) << command.name << " --help lists no options";
  }
  return all;
}

TEST(OptionVocabulary, SharedOptionsAreSpelledAndWrittenTheSameInEveryCommand) {
  const auto all = every_commands_options();
  // Options whose meaning is the same wherever they appear: the same help, word for word
  // (they come from one function). Others shared by name (--model, --out, --poses...) mean
  // "the command's model/output/count" and must at least take a value alike.
  const std::set<std::string> same_text = {"prior-std",
                                           "free",
                                           "fix",
                                           "max-data-size",
                                           "skip-bad-rows",
                                           "progress",
                                           "allow-rank-deficient",
                                           "rcond",
                                           "param-error",
                                           "config-range",
                                           "threads"};
  std::map<std::string, std::pair<std::string, HelpOption>> first;
  for (const auto& [command, options] : all) {
    for (const auto& [name, option] : options) {
      if (name == "help" || name == "version") continue;
      if (!cli::deprecated_alias_target(option.description).empty()) continue;
      const auto seen = first.find(name);
      if (seen == first.end()) {
        first[name] = {command, option};
        continue;
      }
      const auto& [other, reference] = seen->second;
      EXPECT_EQ(option.spec.empty(), reference.spec.empty())
          << "--" << name << " takes a value in " << other << " but not in " << command
          << " (or the other way round)";
      if (same_text.count(name)) {
        EXPECT_EQ(option.spec, reference.spec)
            << "--" << name << ": " << command << " vs " << other;
        EXPECT_EQ(option.description, reference.description)
            << "--" << name << " is described differently in " << command << " and " << other;
      }
    }
  }
  // Noise is a standard deviation wherever it is an option (the paper's half-width only in
  // simulate, named as such), and every command with readings to weigh takes it.
  for (const char* command : {"calibrate", "validate", "observability", "design", "simulate"}) {
    ASSERT_EQ(all.at(command).count("noise-std"), 1u) << command << " has no --noise-std";
    EXPECT_EQ(all.at(command)
                  .at("noise-std")
                  .description.rfind("the readings' noise standard deviation per unit", 0),
              0u)
        << command << ": " << all.at(command).at("noise-std").description;
  }
  for (const char* command : {"calibrate", "observability", "design", "simulate"})
    EXPECT_EQ(all.at(command).count("prior-std"), 1u) << command << " has no --prior-std";
  // Retired spellings survive only as deprecated aliases of an option of the same command.
  const std::set<std::string> retired = {"noise", "count", "legs"};
  for (const auto& [command, options] : all)
    for (const auto& [name, option] : options) {
      const std::string target = cli::deprecated_alias_target(option.description);
      if (target.empty()) {
        EXPECT_EQ(retired.count(name), 0u) << command << " still has --" << name;
        continue;
      }
      EXPECT_EQ(options.count(target), 1u)
          << command << ": --" << name << " aliases --" << target << ", which it does not have";
    }
}

class OptionVocabularyRuns : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("vocabulary");
    ASSERT_EQ(run_cli("model --out " + model()).exit_code, 0);
    const CliResult sim = run_cli("simulate --model " + model() +
                                  " --poses 30 --seed 3 --validation 1 --noise-std 0.0007mm "
                                  "--write-data " +
                                  data());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string model() { return *dir_ / "M.json"; }
  static std::string data() { return *dir_ / "D.csv"; }
  // Each command that takes a prior, with what else it needs to run quickly.
  static std::map<std::string, std::string> with_prior() {
    return {{"calibrate", "calibrate --model " + model() + " --data " + data()},
            {"observability", "observability --model " + model() + " --data " + data()},
            {"design", "design --model " + model() + " --poses 30 --candidates 60 --out " +
                           (*dir_ / "T.csv")},
            {"simulate", "simulate --model " + model() + " --poses 30 --validation 1"}};
  }
  static TempDir* dir_;
};
TempDir* OptionVocabularyRuns::dir_ = nullptr;

TEST_F(OptionVocabularyRuns, EveryPriorFormWorksInEveryCommandThatTakesAPrior) {
  for (const auto& [command, line] : with_prior()) {
    for (const std::string prior : {"2.887mm,0.0058rad", "'leg*=2.887mm'", "'leg*=2.887mm,*.z=0.5'",
                                    "0.5mm --prior-std 'leg1*=1mm'"}) {
      const CliResult run = run_cli(line + " --noise-std 0.0007mm --prior-std " + prior);
      EXPECT_EQ(run.exit_code, 0) << command << " --prior-std " << prior << ": " << run.err;
    }
    const CliResult bad = run_cli(line + " --noise-std 0.0007mm --prior-std 2.887parsec");
    EXPECT_EQ(bad.exit_code, 2) << command;
    EXPECT_NE(bad.err.find("--prior-std '2.887parsec': "), std::string::npos) << command << bad.err;
    const CliResult wrong_unit = run_cli(line + " --noise-std 0.0007mm --prior-std 'leg*=1rad'");
    EXPECT_EQ(wrong_unit.exit_code, 2) << command;
    EXPECT_NE(wrong_unit.err.find("but its std is in rad"), std::string::npos) << wrong_unit.err;
  }
}

TEST_F(OptionVocabularyRuns, NoiseStdIsParsedTheSameEverywhere) {
  auto lines = with_prior();
  // The truth the data was simulated from: held-out readings consistent with 0.0007 mm.
  lines["validate"] = "validate --model " + (*dir_ / "D.truth.json") + " --data " + data();
  for (const auto& [command, line] : lines) {
    const CliResult good = run_cli(line + " --noise-std 0.0007mm");
    EXPECT_EQ(good.exit_code, 0) << command << ": " << good.err;
    const CliResult bad = run_cli(line + " --noise-std 7parsec");
    EXPECT_EQ(bad.exit_code, 2) << command;
    EXPECT_NE(bad.err.find("--noise-std '7parsec': "), std::string::npos) << command << bad.err;
  }
}

TEST_F(OptionVocabularyRuns, OldSpellingsStillWorkWithOneNote) {
  const std::string m = model();
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"simulate --poses 30 --validation 1 --seed 2 --noise 0.00125",
       "simulate --poses 30 --validation 1 --seed 2 --noise-half-width 0.00125"},
      {"design --model " + m + " --count 30 --candidates 60 --noise-std 0.0007mm --out /dev/null",
       "design --model " + m + " --poses 30 --candidates 60 --noise-std 0.0007mm --out /dev/null"},
      {"fk --model " + m + " --legs 354,354,354,354,354,382",
       "fk --model " + m + " --actuators 354,354,354,354,354,382"},
      {"calibrate --model " + m + " --data " + data() + " --report -",
       "calibrate --model " + m + " --data " + data() + " --json -"},
  };
  for (const auto& [old_line, new_line] : pairs) {
    const CliResult old_run = run_cli(old_line), new_run = run_cli(new_line);
    EXPECT_EQ(old_run.exit_code, new_run.exit_code) << old_line << "\n" << old_run.err;
    EXPECT_NE(old_run.err.find("is deprecated: use --"), std::string::npos) << old_line;
    EXPECT_EQ(count_lines(old_run.err), count_lines(new_run.err) + 1) << old_line << old_run.err;
    EXPECT_EQ(new_run.err.find("deprecated"), std::string::npos) << new_line;
    // The same result, but for the solve time that calibrate and simulate print.
    if (old_line.rfind("fk", 0) == 0 || old_line.rfind("design", 0) == 0) {
      EXPECT_EQ(old_run.out, new_run.out) << old_line;
    }
  }
  const CliResult both = run_cli("design --model " + m + " --count 30 --poses 30 --out /dev/null");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("give --poses or --count (its deprecated old name), not both"),
            std::string::npos)
      << both.err;
}

}  // namespace
}  // namespace kincal::testing
