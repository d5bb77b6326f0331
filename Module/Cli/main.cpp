// tissuemosaic: the headless command-line tool. Entry point only: each command lives in its own file (Commands.h),
// the option groups that commands share in CommonOptions.h; CLI11 parses. Exit status: 0 done, 1 an error while
// working (bad data, unreadable file, tracking lost), 2 a command line that does not make sense, 128 + the signal
// (130, 143) when SIGINT or SIGTERM stopped a command that then wrote its partial outputs (StopSignal.h).
#include "CommonOptions.h"
#include "Commands.h"
#include "HelpFormat.h"
#include "OptionNames.h"
#include "StopSignal.h"
#include "UsageMessage.h"
#include "Core/Error.h"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

using namespace tissuemosaic;
using tissuemosaic::cli::commandPath;
using tissuemosaic::cli::usageMessage;

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
  cli::useHouseHelpFormat(tool);

#if !defined(TM_BENCH_ONLY)
  cli::setupStereo(tool);
  CLI::App* synth = tool.add_subcommand("synth", "synthetic stereo data with exact ground truth");
  synth->require_subcommand(1);
  synth->footer("Run a synth command with --help for its options.");
  cli::setupSynthPair(*synth);
  cli::setupSynthScan(*synth);
  cli::setupTrack(tool);
  cli::setupReconstruct(tool);
  cli::setupBatch(tool);
  cli::setupParams(tool);
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
  cli::moveHelpLast(tool);

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
  } catch (const cli::StoppedBySignal& stopped) {
    // The outputs are written; the status tells scripts and batch runners the run is not whole.
    std::cerr << toolName << " " << commandPath(tool) << ": " << stopped.message << "\n";
    return stopped.exitStatus();
  } catch (const ParameterError& error) {  // the engine names the value; the command line names its option
    std::cerr << toolName << " " << commandPath(tool) << ": error: " << cli::withOptionName(error) << "\n";
  } catch (const Error& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": error: " << error.what() << "\n";
  } catch (const cv::Exception& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": OpenCV error: " << error.what() << "\n";
  } catch (const std::exception& error) {
    std::cerr << toolName << " " << commandPath(tool) << ": error: " << error.what() << "\n";
  }
  return 1;
}
