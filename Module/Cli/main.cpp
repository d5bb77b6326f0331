// tissuemosaic: the headless command-line tool. Entry point only: each command lives in its own file (Commands.h),
// the option groups that commands share in CommonOptions.h; CLI11 parses. Exit status: 0 done, 1 an error while
// working (bad data, unreadable file, tracking lost), 2 a command line that does not make sense.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/EditDistance.h"
#include "Core/Error.h"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

using namespace tissuemosaic;

namespace {

#if defined(TM_BENCH_ONLY)
const std::string toolName = "tissuemosaic-bench";
#else
const std::string toolName = "tissuemosaic";
#endif

const char* const toolDetails =
    "Run a command with --help for its options. The commands that read stereo video share their option groups:\n"
    "input (--left-frames/--right-frames, --left-video/--right-video or --video), geometry (--calib rig.yml\n"
    "[--rectified], or --focal-px/--baseline-mm for rectified frames), --device, --params, the disparity range\n"
    "and --quiet mean the same in every command. Exit status: 0 done, 1 error, 2 command-line error.";

/// CLI11's help layout with one blank line between option groups, and without the Needs:/Excludes: lists (each
/// group's descriptions say how its options go together).
class HelpFormatter : public CLI::Formatter {
public:
  std::string make_group(std::string group, bool isPositional, std::vector<const CLI::Option*> options) const override {
    std::string text = group + ":\n";
    for (const CLI::Option* option : options) text += make_option(option, isPositional);
    return text;
  }
  std::string make_usage(const CLI::App* app, std::string name) const override {
    return CLI::Formatter::make_usage(app, name) + "\n";
  }
  std::string make_option_opts(const CLI::Option* option) const override {
    std::string text;
    if (option->get_type_size() == 0) return text;  // a flag
    if (!option->get_type_name().empty()) text += " " + option->get_type_name();
    if (!option->get_default_str().empty()) text += "=" + option->get_default_str();
    if (option->get_required()) text += " REQUIRED";
    return text;
  }
};

/// -h/--help last, under the common options, in every command (CLI11 adds it first).
void moveHelpLast(CLI::App& app) {
  app.set_help_flag();
  app.set_help_flag("-h,--help", "print this help and exit")->group(cli::heading::common);
  for (CLI::App* sub : app.get_subcommands([](CLI::App* candidate) { return !candidate->get_name().empty(); })) {
    moveHelpLast(*sub);
  }
}

/// The deepest command named on the command line (the tool itself when none was).
const CLI::App* selectedCommand(const CLI::App& tool) {
  const CLI::App* command = &tool;
  while (!command->get_subcommands().empty()) command = command->get_subcommands().front();
  return command;
}

/// "stereo", "bench stereo", or "" for the tool itself.
std::string commandPath(const CLI::App& tool) {
  std::string path;
  for (const CLI::App* command = selectedCommand(tool); command->get_parent(); command = command->get_parent()) {
    path = command->get_name() + (path.empty() ? "" : " " + path);
  }
  return path;
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

/// CLI11's message said the house's way: the option or word at fault first, in our words.
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

#if !defined(TM_WITH_REGISTRATION)
/// A command this build leaves out: it takes any words and says why it cannot run.
void addUnavailableCommand(CLI::App& tool, const std::string& name, const std::string& summary,
                           const std::string& reason) {
  CLI::App* command = cli::addCommand(tool, name, summary + " (not in this build)", reason);
  command->allow_extras();
  command->callback([reason] { throw Error(reason); });
}
#endif

}  // namespace

int main(int argc, char** argv) {
  CLI::App tool("TissueMosaic: stereo surgical video to a dense textured 3D model", toolName);
  tool.footer(toolDetails);
  tool.require_subcommand(1);
  tool.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::Throw);
  tool.formatter(std::make_shared<HelpFormatter>());
  tool.get_formatter()->column_width(34);

#if !defined(TM_BENCH_ONLY)
  cli::setupStereo(tool);
  CLI::App* synth = tool.add_subcommand("synth", "synthetic stereo data with exact ground truth");
  synth->require_subcommand(1);
  synth->footer("Run a synth command with --help for its options.");
  cli::setupSynthPair(*synth);
  cli::setupSynthScan(*synth);
  cli::setupTrack(tool);
  cli::setupReconstruct(tool);
#if defined(TM_WITH_REGISTRATION)
  cli::setupRegister(tool);
  cli::setupEval(tool);
#else
  addUnavailableCommand(tool, "register", "registration to a CT/MR surface model",
                        "this build has no registration: it needs VTK (configure with -DTM_WITH_GUI=ON)");
  addUnavailableCommand(tool, "eval", "a reconstruction scored against a known surface",
                        "this build has no evaluation: it needs VTK (configure with -DTM_WITH_GUI=ON)");
#endif
#endif
  CLI::App* bench = tool.add_subcommand("bench", "benchmarks on synthetic data: median milliseconds per stage as JSON");
  bench->require_subcommand(1);
  bench->footer("Run a bench command with --help for its options. tissuemosaic-bench is the same tool with only these "
                "commands\n(no image or video codecs linked), to run on a GPU machine without OpenCV.");
  cli::setupBenchStereo(*bench);
  cli::setupBenchTrack(*bench);
  cli::setupBenchReconstruct(*bench);
  cli::setupBenchPnp(*bench);
  cli::setupBenchOrb(*bench);
  moveHelpLast(tool);

  const std::vector<std::string> words(argv + 1, argv + argc);
  if (words.empty() || words[0] == "help") {
    std::cout << tool.help();
    return words.empty() ? 2 : 0;
  }
  try {
    tool.parse(argc, argv);  // runs the command's callback
    return 0;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return tool.exit(error);  // --help
    const std::string name = commandPath(tool);
    const std::string command = toolName + (name.empty() ? "" : " " + name);
    std::cerr << command << ": error: " << usageMessage(error, tool) << "\n"
              << "run '" << command << " --help' for the options\n";
    return 2;
  } catch (const Error& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": error: " << error.what() << "\n";
  } catch (const cv::Exception& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": OpenCV error: " << error.what() << "\n";
  } catch (const std::exception& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": error: " << error.what() << "\n";
  }
  return 1;
}
