#include "Arguments.h"

#include "Core/Error.h"

#include <cstdlib>

namespace tissuemosaic::cli {

namespace {
bool isOption(const std::string& word) { return word.size() > 2 && word.compare(0, 2, "--") == 0; }
}  // namespace

Arguments::Arguments(const std::vector<std::string>& words) {
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (!isOption(word)) {
      positional_.push_back(word);
      continue;
    }
    std::string name = word.substr(2);
    std::string value;
    const auto equals = name.find('=');
    if (equals != std::string::npos) {
      value = name.substr(equals + 1);
      name = name.substr(0, equals);
    } else if (i + 1 < words.size() && !isOption(words[i + 1])) {
      value = words[++i];
    }
    if (values_.count(name)) throw Error("option --" + name + " is given twice");
    values_[name] = value;
  }
}

bool helpRequested(const std::vector<std::string>& words) {
  for (const std::string& word : words) {
    if (word == "--help" || word == "-h") return true;
  }
  return false;
}

bool Arguments::has(const std::string& name) const { return values_.count(name) != 0; }

std::string Arguments::required(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw Error("missing required option --" + name);
  if (it->second.empty()) throw Error("option --" + name + " needs a value");
  return it->second;
}

std::string Arguments::text(const std::string& name, const std::string& fallback) const {
  return has(name) ? required(name) : fallback;
}

int Arguments::integer(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const std::string value = required(name);
  char* end = nullptr;
  const long parsed = std::strtol(value.c_str(), &end, 10);
  if (end == value.c_str() || *end != '\0' || parsed < -1000000000L || parsed > 1000000000L)
    throw Error("option --" + name + " expects an integer, got '" + value + "'");
  return static_cast<int>(parsed);
}

double Arguments::number(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string value = required(name);
  char* end = nullptr;
  const double parsed = std::strtod(value.c_str(), &end);
  if (end == value.c_str() || *end != '\0') throw Error("option --" + name + " expects a number, got '" + value + "'");
  return parsed;
}

void Arguments::allowOnly(const std::set<std::string>& known) const {
  if (!positional_.empty()) {
    throw Error("unexpected argument '" + positional_.front() + "' (options are written --name value)");
  }
  for (const auto& [name, value] : values_) {
    if (!known.count(name)) throw Error("unknown option --" + name);
  }
}

}  // namespace tissuemosaic::cli
