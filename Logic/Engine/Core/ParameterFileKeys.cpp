#include "Core/ParameterFileKeys.h"

#include "Core/EditDistance.h"
#include "Core/Error.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <yaml-cpp/yaml.h>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace tissuemosaic::parameters {

void requireKnownKeys(const cv::FileNode& given, const cv::FileNode& known, const std::string& nodeName, bool recurse) {
  if (!given.isMap()) return;  // the structs' read() say what a node must be
  const std::vector<std::string> knownKeys = known.isMap() ? known.keys() : std::vector<std::string>{};
  for (const std::string& key : given.keys()) {
    const cv::FileNode knownEntry = known.isMap() ? known[key] : cv::FileNode();
    if (knownEntry.empty()) {
      // Near enough to be a slip: a third of the name, at least 3 edits ("znccWindw" for "znccWindowPx").
      const std::string nearest = nearestName(key, knownKeys, std::max<std::size_t>(3, key.size() / 3));
      std::string message = nodeName.empty() ? "unknown node '" + key + "'"
                                             : "unknown key '" + key + "' in node '" + nodeName + "'";
      if (!nearest.empty()) {
        message += " (did you mean '" + nearest + "'?)";
      } else {
        std::string list;
        for (const std::string& name : knownKeys) list += (list.empty() ? "" : ", ") + name;
        message += " (known " + std::string(nodeName.empty() ? "nodes" : "keys") + ": " + list + ")";
      }
      throw Error(message);
    }
    if (recurse && knownEntry.isMap()) requireKnownKeys(given[key], knownEntry, key, false);
  }
}

YAML::Node requireYamlOpenCvCanRead(const std::string& text, const std::string& context, const std::string& invalid) {
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || text[start] == '<') return {};  // empty (the callers say so) or XML
  // OpenCV's "%YAML:1.0" is not a YAML directive yaml-cpp knows: the rest of the file is plain YAML.
  const std::size_t body = text.compare(start, 5, "%YAML") == 0 ? text.find('\n', start) : start;
  // OpenCV's parser also loops on a line that starts with '-' followed by neither a space (a list item), a number
  // nor "--" (a document start), such as "-~--" (found by fuzz_params), which yaml-cpp reads as part of a scalar.
  // Control bytes (a NUL among them) are no YAML text, and OpenCV's parser looped on some (fuzz_params).
  const auto control = std::find_if(text.begin(), text.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r';
  });
  if (control != text.end()) {
    const long line = 1 + std::count(text.begin(), control, '\n');
    throw Error(context + invalid + " (line " + std::to_string(line) + " holds a control byte)");
  }
  // Lines end at '\n' or "\r\n". A carriage return without a line feed is refused: OpenCV's parser looped on
  // "-\r--" and on "-\r" before other text (fuzz_params).
  std::string unixText;
  unixText.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\r') {
      unixText += text[i];
    } else if (i + 1 >= text.size() || text[i + 1] != '\n') {
      const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(i), '\n');
      throw Error(context + invalid + " (line " + std::to_string(line) +
                  " holds a carriage return without a line feed)");
    }
  }
  std::istringstream lines(unixText);
  int number = 0;
  bool content = false;  // a line with more than blanks came before
  std::size_t rootIndent = std::string::npos;  // of the first key
  for (std::string line; std::getline(lines, line);) {
    ++number;
    // A '%' line other than the "%YAML" header first: OpenCV takes no other directive, and looped on some
    // ("%YAt(" first, once the header was put before it: fuzz_params).
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;  // a blank line
    const bool header = !content && line.compare(first, 5, "%YAML") == 0;
    content = true;
    if (line[first] == '%' && !header) {
      throw Error(context + invalid + " (line " + std::to_string(number) +
                  " is a directive: only a first line '%YAML:1.0' is taken)");
    }
    // One document, whose lines are indented no less than its first key: OpenCV's parser looped on a second
    // document and on a sequence item left of the mapping (yaml-cpp reads the first document only, and took the
    // second text's lines as a scalar; Testing/Fuzz/open/fuzz_params before this).
    if (line[first] != '#' && !header) {
      const bool documentStart = line.compare(first, 3, "---") == 0;
      if (rootIndent == std::string::npos) {
        if (!documentStart) rootIndent = first;
      } else if (documentStart) {
        throw Error(context + invalid + " (line " + std::to_string(number) + " starts a second document)");
      } else if (first < rootIndent) {
        throw Error(context + invalid + " (line " + std::to_string(number) + " is indented less than the first key)");
      }
    }
    if (line[first] != '-' || first + 1 >= line.size()) continue;
    const char next = line[first + 1];
    // "-." alone hung it too, and "-.0--" (fuzz_params): what follows a '-' that is no list item's must be a whole
    // number, to the end of its word.
    const auto wholeNumber = [&] {
      const std::size_t end = line.find_first_of(" \t#,]}", first);  // a number in a flow list ends at , ] }
      const std::string word = line.substr(first, end == std::string::npos ? std::string::npos : end - first);
      char* stop = nullptr;
      std::strtod(word.c_str(), &stop);
      return stop != word.c_str() && *stop == '\0';
    };
    const bool fine = next == ' ' || next == '\t' || line.compare(first, 3, "---") == 0 || wholeNumber();
    if (!fine) throw Error(context + "line " + std::to_string(number) + " starts with '-' but is no list item or number");
  }
  try {
    return YAML::Load(body == std::string::npos ? std::string() : text.substr(body));
  } catch (const YAML::Exception& error) {
    throw Error(context + invalid + " (" + error.msg + " at line " + std::to_string(error.mark.line + 1) + ")");
  }
}

void requireWellFormedYaml(const std::string& text, const std::string& context) {
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || text[start] == '<') return;  // empty (the callers say so) or XML
  const YAML::Node root = requireYamlOpenCvCanRead(text, context);
  require(root.IsMap() && root.size() > 0,
          context + "the file holds no parameter node (such as 'stereo:' or 'tracking:', see Resources/Presets)");
}

cv::FileStorage openOpenCvText(const std::string& text, const std::string& context, const std::string& invalid) {
  // From memory OpenCV tells YAML by its "%YAML" line alone (a file it tells by its name): a YAML text without one
  // gets it, which its parser takes as the header it is.
  const std::size_t start = text.find_first_not_of(" \t\r\n");
  const bool tagged = start == std::string::npos || text[start] == '<' || text[start] == '{' ||
                      text.compare(start, 5, "%YAML") == 0;
  cv::FileStorage storage;
  try {
    storage.open(tagged ? text : "%YAML:1.0\n" + text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& error) {
    // error.err, not what(): OpenCV's source file and line mean nothing to a user.
    throw Error(context + invalid + " (" + error.err + ")");
  } catch (const std::exception& error) {
    // OpenCV's parser lets some of its own failures out as std::length_error (an empty key: "   :").
    throw Error(context + invalid + " (" + error.what() + ")");
  }
  require(storage.isOpened(), context + invalid);
  return storage;
}

cv::FileStorage openParameterText(const std::string& text, const std::string& context, const std::string& invalid) {
  require(text.find_first_not_of(" \t\r\n") != std::string::npos,
          context + "the text is empty (it should hold nodes such as 'stereo:' or 'tracking:', see Resources/Presets)");
  requireWellFormedYaml(text, context);
  const cv::FileStorage storage = openOpenCvText(text, context, invalid);
  require(storage.root().isMap() && storage.root().size() > 0,
          context + "the file holds no parameter node (such as 'stereo:' or 'tracking:', see Resources/Presets)");
  return storage;
}

cv::FileStorage openParameterFile(const std::string& path) {
  const std::string context = "cannot read parameters file '" + path + "': ";
  require(std::filesystem::is_regular_file(path), "cannot open parameters file '" + path + "': file does not exist");
  std::ifstream file(path, std::ios::binary);
  require(file.good(), context + "the file is not readable");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  require(text.find_first_not_of(" \t\r\n") != std::string::npos,
          context + "the file is empty (it should hold nodes such as 'stereo:' or 'tracking:', see Resources/Presets)");
  return openParameterText(text, context, "not a valid YAML/XML file");
}

}  // namespace tissuemosaic::parameters
