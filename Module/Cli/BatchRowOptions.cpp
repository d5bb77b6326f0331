#include "BatchRowOptions.h"

#include "CommonOptions.h"
#include "Commands.h"
#include "UsageMessage.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>

namespace tissuemosaic::cli {

RowFiles rowFiles(const BatchRow& row) {
  const std::filesystem::path folder(row.out);
  return RowFiles{(folder / "model.ply").string(),  (folder / "quality.json").string(),
                  (folder / "timing.json").string(), (folder / "reconstruct.log").string(),
                  (folder / "done.json").string(),   (folder / "failed.json").string()};
}

std::vector<std::string> reconstructArguments(const BatchRow& row) {
  const RowFiles files = rowFiles(row);
  std::vector<std::string> words = {"reconstruct"};
  for (const std::string& word : row.options()) words.push_back(word);
  words.insert(words.end(), {"--out", files.model, "--quality-json", files.quality, "--timing-json", files.timing});
  return words;
}

void checkRowOptions(const BatchRow& row) {
  const std::string where = "manifest row " + std::to_string(row.number) + " (" + row.name + "): ";
  for (const std::string& word : row.options()) {
    for (const char* owned : {"--out", "--quality-json", "--timing-json"}) {
      if (word == owned || word.rfind(std::string(owned) + "=", 0) == 0) {
        throw UsageError(where + owned + " is set by the batch (in the row's out folder): leave it out of args");
      }
    }
  }
  // The tool as main() builds it, with reconstruct only, whose callback checks and runs nothing.
  CLI::App tool("check", "tissuemosaic");
  tool.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::Throw);
  setupReconstruct(tool, CommandUse::ParseOnly);
  std::vector<std::string> words = reconstructArguments(row);
  std::reverse(words.begin(), words.end());  // CLI11 takes the words last first
  try {
    tool.parse(words);
  } catch (const CLI::ParseError& error) {
    throw UsageError(where + usageMessage(error, tool));
  }
}

}  // namespace tissuemosaic::cli
