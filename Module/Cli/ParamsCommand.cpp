// tissuemosaic params: every key of the parameter files with its default, limits, unit and meaning, from the engine's
// parameter tables (the same rows that validate, read and write the files and make the app's spin boxes).
#include "Commands.h"
#include "CommonOptions.h"

#include "Core/Error.h"
#include "Reconstruction/ParameterTables.h"

#include <cstdio>
#include <memory>
#include <string>

namespace tissuemosaic::cli {
namespace {

constexpr const char* kDetails = R"(Each line: node.key default limits [unit] and what it means. A parameters file (--params) holds
these nodes and keys (OpenCV YAML, XML or JSON); missing keys keep their defaults. The nodes agreement and
pipeline are described in docs/RECONSTRUCTION.md.)";

void listParameters(const std::string& node) {
  bool found = false;
  for (const ParameterNodeDescription& described : describeParameterTables()) {
    if (!node.empty() && node != described.node) continue;
    found = true;
    for (const parameters::FieldDescription& field : described.fields) {
      const std::string unit = field.unit.empty() ? "" : " " + field.unit;
      std::printf("%s.%s %s %s%s\n    %s\n", described.node.c_str(), field.key.c_str(), field.defaultText.c_str(),
                  field.limitsText.c_str(), unit.c_str(), field.doc.c_str());
    }
  }
  if (!found) throw UsageError("--node: no parameter table '" + node + "' (stereo, features, tracking, refinement, fusion)");
}

}  // namespace

void setupParams(CLI::App& tool) {
  CLI::App* command =
      addCommand(tool, "params", "list the parameters: key, default, limits, unit and meaning", kDetails);
  auto node = std::make_shared<std::string>();
  command->add_option("--node", *node, "only this node (stereo, features, tracking, refinement, fusion)")
      ->type_name("NAME")
      ->group(heading::options);
  command->callback([node] { listParameters(*node); });
}

}  // namespace tissuemosaic::cli
