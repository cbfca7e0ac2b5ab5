// The key=value arguments of the tools (hair_study, groom_study, hair_soak), in one place
// (issue 35): a program or study declares its keys once, as a table of Key, and the same
// table parses and checks the command line and writes the usage text.
//
// A value is checked when the command line is parsed, every key given: an unknown key, a key
// given twice, a number out of its range, a word not among the choices, a model that
// hair::parseModel does not know: an error naming the key, the value and what it may be.
#pragma once

#include "common/Status.h"
#include "simulation/ModelRegistry.h"

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace hair::tools
{

enum class Kind
{
  Integer, ///< a whole number in [lo, hi] (0/1 for a switch)
  Number,  ///< a finite number in [lo, hi] ("a/b" accepted: dt=1/30)
  List,    ///< comma-separated numbers, each in [lo, hi]
  Text,    ///< any text (file names; lists of names the study reads itself)
  Choice,  ///< one of `choices`
  Model    ///< a model name, through hair::parseModel (or one of `choices`, e.g. "both")
};

/// One key of a program or study.
struct Key
{
  std::string name;
  Kind kind = Kind::Text;
  /// The default as it would be written on the command line ("1/30", "5e-11,1e-10"), or ""
  /// when there is none (an output file the study asks for, or "the preset's"). With
  /// `computed`, a description of the default, which the study works out itself.
  std::string fallback;
  double lo = 0, hi = 0;
  bool loOpen = false; ///< (lo, hi] instead of [lo, hi]
  std::vector<std::string> choices;
  std::string help;
  bool computed = false; ///< the default depends on other keys: the study gives it
  bool hidden = false;   ///< for the program itself (a child process): left out of the usage
  std::string shownAs;   ///< the usage's placeholder when there is no default ("<csv>")

  Key& as(std::string placeholder)
  {
    shownAs = std::move(placeholder);
    return *this;
  }

  Key& computedDefault()
  {
    computed = true;
    return *this;
  }
  Key& hide()
  {
    hidden = true;
    return *this;
  }
  Key& openBelow()
  {
    loOpen = true;
    return *this;
  }
};

using Keys = std::vector<Key>;

Key integerKey(std::string name, std::string fallback, double lo, double hi, std::string help);
Key numberKey(std::string name, std::string fallback, double lo, double hi, std::string help);
Key listKey(std::string name, std::string fallback, double lo, double hi, std::string help);
Key textKey(std::string name, std::string fallback, std::string help);
Key choiceKey(std::string name, std::string fallback, std::vector<std::string> choices,
              std::string help);
Key modelKey(std::string name, std::string fallback, std::string help,
             std::vector<std::string> extra = {});

/// The shortest text that reads back as `v` ("0.25", "1.2e-03" → "0.0012"): defaults taken
/// from Core's parameter structs are shown as they are.
std::string shortest(double v);

/// The parsed command line of one program or study.
class Arguments
{
public:
  /// Parses argv[first], … against `keys` (which must outlive this). `owner` names who takes
  /// them in the message for an unknown key ("this study", "groom_study").
  Status parse(int argc, char** argv, int first, const Keys& keys,
               const std::string& owner = "this study");

  bool has(const std::string& key) const { return Values.count(key) > 0; }

  /// The value given, or the table's default. The forms with `fallback` are for the keys
  /// whose default is computed (Key::computed) and only for them.
  int integer(const std::string& key) const;
  int integer(const std::string& key, int fallback) const;
  double number(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  std::vector<double> list(const std::string& key) const;
  /// Text, Choice and Model keys: the word given, or the default.
  std::string text(const std::string& key) const;
  /// Any key's value as written on the command line, or its default as the table writes it.
  std::string written(const std::string& key) const;
  /// A Model key's model (not one of its extra words).
  ModelType model(const std::string& key) const;

private:
  const Key& find(const std::string& key, std::initializer_list<Kind> kinds) const;
  const Keys* Table = nullptr;
  std::map<std::string, std::string> Values;
};

/// `[key=default] …` for every key not hidden, wrapped at `width` columns after `indent`.
std::string usageLine(const Keys& keys, std::size_t indent, std::size_t width = 92);
/// One line per key: its name, default, range or choices, and help.
void describe(std::ostream& out, const Keys& keys);

} // namespace hair::tools
