#include "UsageMessage.h"

#include "Core/EditDistance.h"

#include <regex>
#include <vector>

namespace tissuemosaic::cli {
namespace {

/// The deepest command named on the command line (the tool itself when none was).
const CLI::App* selectedCommand(const CLI::App& tool) {
  const CLI::App* command = &tool;
  while (!command->get_subcommands().empty()) command = command->get_subcommands().front();
  return command;
}

/// " (did you mean --x?)" when one of the command's options is a near miss of `word`, else "".
std::string suggestion(const CLI::App& command, const std::string& word) {
  std::string best;
  std::size_t bestDistance = 3;  // at most two edits away
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) {
      const std::size_t distance = editDistance(word, "--" + name);
      if (distance < bestDistance) {
        bestDistance = distance;
        best = "--" + name;
      }
    }
  }
  return best.empty() ? "" : " (did you mean " + best + "?)";
}

std::string commandList(const CLI::App& parent) {
  std::string list;
  for (const CLI::App* sub : parent.get_subcommands([](const CLI::App*) { return true; })) {
    if (!sub->get_name().empty()) list += (list.empty() ? "" : ", ") + sub->get_name();
  }
  return list;
}

template <class Kind>
bool isA(const CLI::ParseError& error) {
  return dynamic_cast<const Kind*>(&error) != nullptr;
}

}  // namespace

std::string commandPath(const CLI::App& tool) {
  std::string path;
  for (const CLI::App* command = selectedCommand(tool); command->get_parent(); command = command->get_parent()) {
    path = command->get_name() + (path.empty() ? "" : " " + path);
  }
  return path;
}

std::string usageMessage(const CLI::ParseError& error, const CLI::App& tool) {
  const CLI::App& command = *selectedCommand(tool);
  const std::string what = error.what();
  std::smatch match;
  if (isA<CLI::ExtrasError>(error) || what == "A subcommand is required") {
    const std::vector<std::string> extras = command.remaining();
    const bool wantsCommand = what == "A subcommand is required";
    const std::string prefix = command.get_parent() ? command.get_name() + " " : "";
    if (extras.empty()) return "a command is required: " + commandList(command);
    const std::string& word = extras.front();
    if (word.size() > 1 && word[0] == '-') {
      const std::string name = word.substr(0, word.find('='));
      return "unknown option " + name + suggestion(command, name);
    }
    if (wantsCommand) return "unknown command '" + prefix + word + "' (commands: " + commandList(command) + ")";
    return "unexpected argument '" + word + "' (options are written --name value)";
  }
  if (isA<CLI::RequiredError>(error) && std::regex_match(what, match, std::regex("(-\\S+) is required"))) {
    return "missing required option " + match[1].str();
  }
  if (isA<CLI::ConversionError>(error) &&
      std::regex_match(what, match, std::regex("Could not convert: (-\\S+) = (.*)"))) {
    const CLI::Option* option = command.get_option_no_throw(match[1].str());
    const std::string type = option ? option->get_type_name() : "";
    const std::string expected = type == "INT" || type == "UINT" ? "an integer" : type == "FLOAT" ? "a number" : "";
    if (!expected.empty()) {
      return "option " + match[1].str() + " expects " + expected + ", got '" + match[2].str() + "'";
    }
  }
  if (isA<CLI::ArgumentMismatch>(error) && std::regex_match(what, match, std::regex("(-\\S+): At Most 1 required.*"))) {
    return "option " + match[1].str() + " is given twice";
  }
  if (isA<CLI::ArgumentMismatch>(error) && std::regex_match(what, match, std::regex("(-\\S+): [0-9]+ required .* missing"))) {
    return "option " + match[1].str() + " needs a value";
  }
  return what;
}

}  // namespace tissuemosaic::cli
