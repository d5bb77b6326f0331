#include "Commands.h"

namespace tissuemosaic::cli {

CLI::App* addCommand(CLI::App& parent, const std::string& name, const std::string& summary,
                     const std::string& details) {
  CLI::App* command = parent.add_subcommand(name, summary);
  command->footer(details);
  return command;
}

}  // namespace tissuemosaic::cli
