#include "HelpFormat.h"

#include "CommonOptions.h"

#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic::cli {
namespace {

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

}  // namespace

void useHouseHelpFormat(CLI::App& app) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::Throw);
  app.formatter(std::make_shared<HelpFormatter>());
  app.get_formatter()->column_width(34);
}

void moveHelpLast(CLI::App& app) {
  app.set_help_flag();
  app.set_help_flag("-h,--help", "print this help and exit")->group(heading::common);
  for (CLI::App* sub : app.get_subcommands([](CLI::App* candidate) { return !candidate->get_name().empty(); })) {
    moveHelpLast(*sub);
  }
}

}  // namespace tissuemosaic::cli
