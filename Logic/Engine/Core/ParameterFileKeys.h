#pragma once
/// @file ParameterFileKeys.h
/// @brief Parameter files are strict: a misspelt node or key is an error naming it and the nearest known name, never
/// silently ignored. The known names come from the parameter structs' own write() (one source of truth).
#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include <string>

namespace tissuemosaic::parameters {

/// Throws Error unless every key of the map `given` is a key of `known`:
/// "unknown key 'znccWindw' in node 'stereo' (did you mean 'znccWindowPx'?)", or for the file's top level (nodeName
/// empty) "unknown node 'fusoin' (did you mean 'fusion'?)". With `recurse`, the keys of each known sub-map are
/// checked too.
void requireKnownKeys(const cv::FileNode& given, const cv::FileNode& known, const std::string& nodeName, bool recurse);

/// Throws Error (prefixed with `context`) unless a YAML parameters text parses with yaml-cpp as a map: OpenCV 4.6's
/// own YAML parser never returns on some malformed texts (" L:0\n-a--", found by fuzz_params), so a text goes to
/// it only once a careful parser has read it. XML texts (starting with '<') are left to OpenCV.
void requireWellFormedYaml(const std::string& text, const std::string& context);
/// The same guard for any OpenCV YAML text (calibration files too): throws Error (`context`, then `invalid` and
/// yaml-cpp's reason, or the line OpenCV would loop on) unless
/// yaml-cpp reads it (an OpenCV "%YAML:1.0" first line skipped) and no line is one OpenCV 4.6 loops on; returns what
/// yaml-cpp read (a null node for an empty or XML text, which OpenCV reads alone).
YAML::Node requireYamlOpenCvCanRead(const std::string& text, const std::string& context,
                                    const std::string& invalid = "not a valid YAML/XML file");

/// Opens an OpenCV YAML (with or without its "%YAML:1.0" line), XML or JSON text from memory, once a guard above
/// has read it; OpenCV's exceptions and a text it cannot open become an Error: `context`, `invalid` and why.
cv::FileStorage openOpenCvText(const std::string& text, const std::string& context, const std::string& invalid);

/// Opens a parameters file (OpenCV YAML/XML) for reading; an empty, missing or malformed file is an Error that says so
/// (never OpenCV's assertion text). The file is read once: the guard above and OpenCV both take its text.
cv::FileStorage openParameterFile(const std::string& path);
/// The same for a parameters text in memory (a preset, a file's contents): OpenCV YAML with or without its
/// "%YAML:1.0" line, XML or JSON. Errors start with `context`; a text no parser reads says `invalid` and why.
cv::FileStorage openParameterText(const std::string& text, const std::string& context, const std::string& invalid);

}  // namespace tissuemosaic::parameters
