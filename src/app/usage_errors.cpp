#include "app/usage_errors.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>

#include "core/similar_names.h"

namespace vf::app {

namespace {

std::vector<std::string> optionNames(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  return names;
}

std::vector<std::string> commandNames(const CLI::App& root) {
  std::vector<std::string> names;
  for (const CLI::App* command : root.get_subcommands({})) names.push_back(command->get_name());
  return names;
}

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

// One line per word the command did not take. The word after an unknown option is taken to be
// that option's value and is not reported again.
std::vector<std::string> unknownWords(const std::vector<std::string>& words, const std::vector<std::string>& options) {
  std::vector<std::string> lines;
  bool after_unknown_option = false;
  for (const std::string& word : words) {
    if (word == "--") continue;  // the end of the options, not a word of its own
    const bool is_option = word.size() > 1 && word[0] == '-';
    if (is_option) {
      std::string name = word.substr(0, word.find('='));
      if (name.find_first_not_of('-') == std::string::npos) name = word;  // "--=x"
      lines.push_back("unknown option " + name + didYouMean(likelyNames(name, options)));
    } else if (!after_unknown_option) {
      lines.push_back("unexpected argument '" + word + "'");
    }
    after_unknown_option = is_option && word.find('=') == std::string::npos;
  }
  return lines;
}

// The value of a numeric option as strtold reads it (as CLI11 does: hex, "nan", "inf" too), or
// nullopt when it is not a number at all (CLI11's own conversion then says so).
std::optional<long double> numberIn(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const long double v = std::strtold(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return v;
}

std::string shortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Why `v` (read from `text`) is no value for a float option, or "" when it is one: a value
// beyond FLT_MAX becomes inf on conversion.
std::string notAFloat(long double v, const std::string& text) {
  if (!std::isfinite(v)) return "must be a finite number, got " + text;
  if (std::fabs(v) > FLT_MAX) return "must be at most 3.4e+38 in size, got " + text;
  return "";
}

CLI::Validator bound(std::function<bool(long double)> ok, const std::string& rule, const std::string& name) {
  return CLI::Validator(
      [ok, rule](std::string& text) -> std::string {
        const std::optional<long double> v = numberIn(text);
        if (!v) return "";
        const std::string why = notAFloat(*v, text);
        if (!why.empty()) return why;
        return ok(*v) ? "" : "must be " + rule + ", got " + text;
      },
      rule, name);
}

}  // namespace

CLI::Validator atLeast(double min) {
  return bound([min](long double v) { return v >= min; }, "at least " + shortNumber(min), "AT_LEAST");
}

CLI::Validator inRange(double min, double max) {
  return bound([min, max](long double v) { return v >= min && v <= max; },
               "between " + shortNumber(min) + " and " + shortNumber(max), "IN_RANGE");
}

void requireFiniteNumbers(CLI::App& app) {
  const CLI::Validator finite_number(
      [](std::string& text) -> std::string {
        const std::optional<long double> v = numberIn(text);
        return v ? notAFloat(*v, text) : "";
      },
      "", "FINITE");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_name().rfind("FLOAT", 0) == 0) option->check(finite_number);
  for (CLI::App* command : app.get_subcommands({})) requireFiniteNumbers(*command);
}

int reportParseError(CLI::App& root, const CLI::ParseError& error, const std::string& program) {
  if (error.get_exit_code() == 0) return root.exit(error);  // --help, --version
  const std::vector<CLI::App*> parsed = root.get_subcommands();
  CLI::App* command = parsed.empty() ? nullptr : parsed.front();
  std::vector<std::string> lines;
  if (command) {
    lines = unknownWords(command->remaining(), optionNames(*command));
  } else if (!root.get_subcommands({}).empty()) {
    // No command was recognised: the first plain word is the command the user meant.
    std::vector<std::string> words = root.remaining();
    words.erase(std::remove(words.begin(), words.end(), "--"), words.end());
    const auto first_word = std::find_if(words.begin(), words.end(), [](const std::string& w) { return w[0] != '-'; });
    if (first_word != words.end()) {
      const std::vector<std::string> names = commandNames(root);
      lines.push_back("unknown command '" + *first_word + "'" + didYouMean(likelyNames(*first_word, names), "'") +
                      "; the commands are " + joined(names));
    } else if (!words.empty()) {
      lines = unknownWords(words, optionNames(root));
    } else {
      lines.push_back("no command given; the commands are " + joined(commandNames(root)));
    }
  } else {
    lines = unknownWords(root.remaining(), optionNames(root));  // a program without commands
  }
  if (lines.empty()) lines.push_back(error.what());  // a missing or malformed value: CLI11 says it well
  const bool has_commands = !root.get_subcommands({}).empty();
  const std::string name = command ? program + " " + command->get_name() : program;
  for (const std::string& line : lines) std::fprintf(stderr, "%s: %s\n", name.c_str(), line.c_str());
  const char* help_lists = command || !has_commands ? "its options" : "the commands";
  std::fprintf(stderr, "Run '%s --help' for %s.\n", name.c_str(), help_lists);
  return error.get_exit_code();
}

CLI::Validator existingFile() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) return noSuchPathMessage(path, "file");
        if (std::filesystem::is_directory(path, ec)) return path + ": a folder, not a file";
        return "";
      },
      "FILE");
}

CLI::Validator existingPath() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        std::error_code ec;
        return std::filesystem::exists(path, ec) ? "" : noSuchPathMessage(path);
      },
      "PATH");
}

}  // namespace vf::app
