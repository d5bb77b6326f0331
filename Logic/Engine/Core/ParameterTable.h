#pragma once
/// @file ParameterTable.h
/// @brief One table of fields per parameter struct: each row names a member once, with its file key, limits, unit
/// and one-line doc. The struct's validate() (the range checks), its parameter-file node (write and read), the Qt
/// panels' spin boxes (limits, suffix, tooltip), the command line's parameter list and the Python dict all come
/// from it, so a parameter added as one row appears everywhere and its limits exist once. Defaults stay the struct's
/// member initialisers (Field::defaultValue reads them). Rules between fields (min <= max, odd windows) stay in the
/// struct's validate(), after the table's checks.
#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

#include <cmath>
#include <cstddef>
#include <functional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace tissuemosaic::parameters {

/// How a field is stored, written and read: numbers keep their C++ type in the file (OpenCV writes ints, floats and
/// doubles differently); a choice is an enum (or bool) written as one of its names.
enum class FieldKind { Integer, Float, Double, Choice };

template <class S>
struct Field {
  const char* key;   ///< the member's name: the file key, the Python dict key, the spin box's object name prefix
  FieldKind kind;
  double minimum;    ///< inclusive limits (numbers only)
  double maximum;
  const char* unit;  ///< "px", "mm", "deg", "frames", ... or "" (a plain number)
  const char* doc;   ///< what it means, for tooltips and the command line's list
  std::function<double(const S&)> get;        ///< a choice as its enum value
  std::function<void(S&, double)> set;
  std::vector<std::string> choiceNames;       ///< a choice's names, in the order of choiceValues
  std::vector<int> choiceValues;
  std::size_t offset = 0, size = 0;           ///< where the member lies in S (the test that every member has a row)

  bool integer() const { return kind == FieldKind::Integer; }
  double defaultValue() const { return get(S{}); }
  /// A choice's name for `value` (Error for none).
  const std::string& choiceName(double value) const {
    for (std::size_t i = 0; i < choiceValues.size(); ++i) {
      if (choiceValues[i] == static_cast<int>(value)) return choiceNames[i];
    }
    throw Error(std::string("parameter ") + key + " holds a value without a name");
  }
  /// "a", "b" or "c" (quoted), for messages and help.
  std::string choicesText() const {
    std::string text;
    for (std::size_t i = 0; i < choiceNames.size(); ++i) {
      text += (i == 0 ? "" : i + 1 == choiceNames.size() ? " or " : ", ") + ("\"" + choiceNames[i] + "\"");
    }
    return text;
  }
};

namespace detail {
template <class S, class T>
std::size_t offsetOf(T S::*member) {
  static const S probe{};
  return static_cast<std::size_t>(reinterpret_cast<const char*>(&(probe.*member)) -
                                  reinterpret_cast<const char*>(&probe));
}
}  // namespace detail

/// A number row: int (and bool, as 0/1), float or double member within [minimum, maximum].
template <class S, class T>
Field<S> number(const char* key, T S::*member, double minimum, double maximum, const char* unit, const char* doc) {
  static_assert(std::is_arithmetic_v<T>, "number() takes int, bool, float or double members");
  const FieldKind kind = std::is_integral_v<T> ? FieldKind::Integer
                         : std::is_same_v<T, float> ? FieldKind::Float
                                                    : FieldKind::Double;
  Field<S> field{key, kind, minimum, maximum, unit, doc,
                 [member](const S& s) { return static_cast<double>(s.*member); },
                 [member, key](S& s, double value) {
                   if constexpr (std::is_same_v<T, bool>) {
                     if (value != 0 && value != 1) throw Error(std::string(key) + " must be 0 or 1");
                     s.*member = value != 0;
                   }
                   else if constexpr (std::is_integral_v<T>) s.*member = static_cast<T>(std::llround(value));
                   else s.*member = static_cast<T>(value);
                 },
                 {}, {}};
  field.offset = detail::offsetOf(member);
  field.size = sizeof(T);
  return field;
}

/// A choice row: an enum (or bool) member written as name(value), one of `values`.
template <class S, class E, class Name>
Field<S> choice(const char* key, E S::*member, std::initializer_list<E> values, Name name, const char* doc) {
  Field<S> field{key, FieldKind::Choice, 0, 0, "", doc,
                 [member](const S& s) { return static_cast<double>(static_cast<int>(s.*member)); },
                 [member](S& s, double value) { s.*member = static_cast<E>(static_cast<int>(value)); },
                 {}, {}};
  for (E value : values) {
    field.choiceNames.emplace_back(name(value));
    field.choiceValues.push_back(static_cast<int>(value));
  }
  field.offset = detail::offsetOf(member);
  field.size = sizeof(E);
  return field;
}

/// A row in words, for help texts: its limits ("[-1000, 1000]", or the choices "paper | ad-census") and default as
/// they would be written.
struct FieldDescription {
  std::string key, defaultText, limitsText, unit, doc;
};

/// The rows of one struct and what they make: range checks, the file node's write and read.
template <class S>
class Table {
public:
  /// `node`: the parameter files' node ("stereo"); `group`: the name errors give ("stereo parameter ...").
  Table(const char* node, const char* group, std::vector<Field<S>> fields)
      : Node(node), Group(group), Fields(std::move(fields)) {}

  const char* node() const { return Node; }
  const char* group() const { return Group; }
  const std::vector<Field<S>>& fields() const { return Fields; }
  /// The row of `key`; Error when there is none.
  const Field<S>& field(const std::string& key) const {
    for (const Field<S>& f : Fields) {
      if (key == f.key) return f;
    }
    throw Error(std::string("no ") + Group + " parameter '" + key + "'");
  }

  /// Throws Error "<group> parameter <key> = <value> is out of range [low, high]" for the first number outside its
  /// limits, in the table's order.
  void requireInRange(const S& s) const {
    for (const Field<S>& f : Fields) {
      if (f.kind == FieldKind::Choice) continue;
      if (f.integer()) {
        parameters::requireRange<long long>(Group, f.key, static_cast<long long>(f.get(s)),
                                            static_cast<long long>(f.minimum), static_cast<long long>(f.maximum));
      } else if (f.kind == FieldKind::Float) {
        // In float, as the member holds it: a limit of 0.01 takes the member's 0.01f.
        parameters::requireRange<float>(Group, f.key, static_cast<float>(f.get(s)), static_cast<float>(f.minimum),
                                        static_cast<float>(f.maximum));
      } else {
        parameters::requireRange<double>(Group, f.key, f.get(s), f.minimum, f.maximum);
      }
    }
  }

  /// Writes the node with every row, in the table's order.
  void write(const S& s, cv::FileStorage& storage) const {
    storage << Node << "{";
    for (const Field<S>& f : Fields) {
      storage << f.key;
      switch (f.kind) {
        case FieldKind::Integer: storage << static_cast<int>(f.get(s)); break;
        case FieldKind::Float: storage << static_cast<float>(f.get(s)); break;
        case FieldKind::Double: storage << f.get(s); break;
        case FieldKind::Choice: storage << f.choiceName(f.get(s)); break;
      }
    }
    storage << "}";
  }

  /// Reads the keys present in `node` into s (missing keys keep s's values); a node that is no map, a number of the
  /// wrong type or an unknown choice is an Error. Does not validate.
  void read(const cv::FileNode& node, S& s) const {
    if (node.empty()) return;
    if (!node.isMap()) throw Error(std::string("the '") + Node + "' parameter node must be a map");
    for (const Field<S>& f : Fields) {
      const cv::FileNode entry = node[f.key];
      if (entry.empty()) continue;
      switch (f.kind) {
        case FieldKind::Integer: readNumber<int>(node, f, s); break;
        case FieldKind::Float: readNumber<float>(node, f, s); break;
        case FieldKind::Double: readNumber<double>(node, f, s); break;
        case FieldKind::Choice: readChoice(entry, f, s); break;
      }
    }
  }

  /// Every row in words, in the table's order.
  std::vector<FieldDescription> describe() const {
    std::vector<FieldDescription> rows;
    for (const Field<S>& f : Fields) {
      FieldDescription row{f.key, "", "", f.unit, f.doc};
      const double value = f.defaultValue();
      if (f.kind == FieldKind::Choice) {
        row.defaultText = f.choiceName(value);
        for (const std::string& name : f.choiceNames) row.limitsText += (row.limitsText.empty() ? "" : " | ") + name;
      } else {
        row.defaultText = numberText(value, f.integer());
        row.limitsText = "[" + numberText(f.minimum, f.integer()) + ", " + numberText(f.maximum, f.integer()) + "]";
      }
      rows.push_back(row);
    }
    return rows;
  }

  /// A struct from `node` (the defaults where it holds no key), validated: the struct's read().
  S readValidated(const cv::FileNode& node) const {
    S s;
    read(node, s);
    s.validate();
    return s;
  }

private:
  static std::string numberText(double value, bool integer) {
    std::ostringstream text;
    if (integer) text << static_cast<long long>(value);
    else text << static_cast<float>(value);  // as a float prints: 0.01, not 0.0099999998
    return text.str();
  }
  template <class T>
  void readNumber(const cv::FileNode& node, const Field<S>& f, S& s) const {
    T value{};
    parameters::readKey(Group, node, f.key, value);
    try {
      f.set(s, static_cast<double>(value));
    } catch (const Error& error) {
      throw Error(std::string(Group) + " parameter " + error.what());  // a bool's "must be 0 or 1"
    }
  }
  void readChoice(const cv::FileNode& entry, const Field<S>& f, S& s) const {
    const std::string text = entry.isString() ? static_cast<std::string>(entry) : std::string();
    for (std::size_t i = 0; i < f.choiceNames.size(); ++i) {
      if (entry.isString() && text == f.choiceNames[i]) {
        f.set(s, f.choiceValues[i]);
        return;
      }
    }
    throw Error(std::string(Group) + " parameter " + f.key + " must be " + f.choicesText() +
                (entry.isString() ? ", not '" + text + "'" : std::string()));
  }

  const char* Node;
  const char* Group;
  std::vector<Field<S>> Fields;
};

}  // namespace tissuemosaic::parameters
