#include "app/usage_errors.h"

#include <algorithm>
#include <cstdio>

namespace vf::app {

int typoDistance(const std::string& a, const std::string& b) {
  // Optimal string alignment over three rows of the table.
  const size_t n = a.size(), m = b.size();
  std::vector<int> before(m + 1), previous(m + 1), current(m + 1);
  for (size_t j = 0; j <= m; ++j) previous[j] = int(j);
  for (size_t i = 1; i <= n; ++i) {
    current[0] = int(i);
    for (size_t j = 1; j <= m; ++j) {
      const int substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        current[j] = std::min(current[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, current);
  }
  return previous[m];
}

std::vector<std::string> likelyNames(const std::string& word, const std::vector<std::string>& candidates) {
  const auto bare = [](const std::string& s) { return s.substr(std::min(s.find_first_not_of('-'), s.size())); };
  const std::string w = bare(word);
  if (w.empty()) return {};
  // One edit in a short word, up to three in a long one: "--voxel-szie-m" finds "--voxel-size-m",
  // "--formt" does not find "--force".
  const int allowed = w.size() <= 5 ? 1 : w.size() <= 9 ? 2 : 3;
  std::string best;
  int best_distance = allowed + 1;
  for (const std::string& candidate : candidates) {
    const int d = typoDistance(w, bare(candidate));
    if (d < best_distance) best = candidate, best_distance = d;
  }
  if (!best.empty()) return {best};
  // A part of a name: "--max-depth" for "--max-depth-m", "--classes" for "--include-classes"
  // and "--exclude-classes".
  std::vector<std::string> containing;
  for (const std::string& candidate : candidates)
    if (w.size() >= 3 && bare(candidate).find(w) != std::string::npos) containing.push_back(candidate);
  if (containing.size() > 3) containing.clear();  // too general to help
  return containing;
}

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

// " (did you mean a, b or c?)", quoted when the names are commands.
std::string suggestion(const std::vector<std::string>& names, const char* quote = "") {
  if (names.empty()) return "";
  std::string out = " (did you mean ";
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + (quote + names[i] + quote);
  return out + "?)";
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
      lines.push_back("unknown option " + name + suggestion(likelyNames(name, options)));
    } else if (!after_unknown_option) {
      lines.push_back("unexpected argument '" + word + "'");
    }
    after_unknown_option = is_option && word.find('=') == std::string::npos;
  }
  return lines;
}

}  // namespace

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
      lines.push_back("unknown command '" + *first_word + "'" + suggestion(likelyNames(*first_word, names), "'") +
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

}  // namespace vf::app
