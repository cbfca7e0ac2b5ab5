#include "StudyArguments.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <utility>

namespace hair::tools
{

namespace
{

/// A finite number; "a/b" is accepted (dt=1/30).
bool toNumber(const std::string& t, double& v)
{
  const auto slash = t.find('/');
  if (slash != std::string::npos)
  {
    double a = 0, b = 0;
    if (!toNumber(t.substr(0, slash), a) || !toNumber(t.substr(slash + 1), b) || b == 0)
      return false;
    v = a / b;
    return std::isfinite(v);
  }
  try
  {
    std::size_t used = 0;
    v = std::stod(t, &used);
    return used == t.size() && std::isfinite(v);
  }
  catch (const std::exception&)
  {
    return false;
  }
}

bool inRange(const Key& k, double v)
{
  return (k.loOpen ? v > k.lo : v >= k.lo) && v <= k.hi;
}

std::string range(const Key& k)
{
  std::ostringstream s;
  s << (k.loOpen ? "(" : "[") << k.lo << ", " << k.hi << "]";
  return s.str();
}

std::string joined(const std::vector<std::string>& words)
{
  std::string list;
  for (const std::string& w : words)
    list += (list.empty() ? "" : ", ") + w;
  return list;
}

/// A mistake in a table or in a study's use of it: a bug, not bad input.
[[noreturn]] void internalError(const std::string& message)
{
  std::cerr << "internal error in the arguments' tables: " << message << "\n";
  std::abort();
}

std::vector<std::string> split(const std::string& text)
{
  std::vector<std::string> items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    items.push_back(item);
  return items;
}

/// Checks `value` of key `k`; the messages are those hair_study has always given.
Status check(const Key& k, const std::string& value)
{
  switch (k.kind)
  {
  case Kind::Integer:
  case Kind::Number:
  {
    double v = 0;
    if (!toNumber(value, v) || !inRange(k, v))
      return Status::Error("argument " + k.name + "=" + value + " must be a number in " + range(k) +
                           ".");
    if (k.kind == Kind::Integer && v != std::floor(v))
      return Status::Error("argument " + k.name + "=" + value + " must be a whole number.");
    return Status::Ok();
  }
  case Kind::List:
  {
    const std::vector<std::string> items = split(value);
    for (const std::string& item : items)
    {
      double v = 0;
      if (!toNumber(item, v) || !inRange(k, v))
        return Status::Error("argument " + k.name + ": '" + item + "' is not a number in " +
                             range(k) + ".");
    }
    if (items.empty())
      return Status::Error("argument " + k.name + " is an empty list.");
    return Status::Ok();
  }
  case Kind::Text:
    return Status::Ok();
  case Kind::Choice:
    for (const std::string& c : k.choices)
      if (value == c)
        return Status::Ok();
    return Status::Error(k.name + "=" + value + " is not one of " + joined(k.choices) + ".");
  case Kind::Model:
  {
    for (const std::string& c : k.choices)
      if (value == c)
        return Status::Ok();
    ModelType type;
    return parseModel(value, k.name + "=", type);
  }
  }
  return Status::Ok();
}

Key make(std::string name, Kind kind, std::string fallback, std::string help)
{
  Key k;
  k.name = std::move(name);
  k.kind = kind;
  k.fallback = std::move(fallback);
  k.help = std::move(help);
  return k;
}

Key ranged(std::string name, Kind kind, std::string fallback, double lo, double hi,
           std::string help)
{
  Key k = make(std::move(name), kind, std::move(fallback), std::move(help));
  k.lo = lo;
  k.hi = hi;
  return k;
}

} // namespace

Key integerKey(std::string name, std::string fallback, double lo, double hi, std::string help)
{
  return ranged(std::move(name), Kind::Integer, std::move(fallback), lo, hi, std::move(help));
}
Key numberKey(std::string name, std::string fallback, double lo, double hi, std::string help)
{
  return ranged(std::move(name), Kind::Number, std::move(fallback), lo, hi, std::move(help));
}
Key listKey(std::string name, std::string fallback, double lo, double hi, std::string help)
{
  return ranged(std::move(name), Kind::List, std::move(fallback), lo, hi, std::move(help));
}
Key textKey(std::string name, std::string fallback, std::string help)
{
  return make(std::move(name), Kind::Text, std::move(fallback), std::move(help));
}
Key choiceKey(std::string name, std::string fallback, std::vector<std::string> choices,
              std::string help)
{
  Key k = make(std::move(name), Kind::Choice, std::move(fallback), std::move(help));
  k.choices = std::move(choices);
  return k;
}
Key modelKey(std::string name, std::string fallback, std::string help,
             std::vector<std::string> extra)
{
  Key k = make(std::move(name), Kind::Model, std::move(fallback), std::move(help));
  k.choices = std::move(extra);
  return k;
}

std::string shortest(double v)
{
  char buffer[32];
  if (v == std::floor(v) && std::abs(v) < 1e15)
  {
    std::snprintf(buffer, sizeof buffer, "%.0f", v);
    return buffer;
  }
  for (int digits = 1; digits <= 17; ++digits)
  {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    if (std::strtod(buffer, nullptr) == v)
      break;
  }
  return buffer;
}

Status Arguments::parse(int argc, char** argv, int first, const Keys& keys,
                        const std::string& owner)
{
  Table = &keys;
  for (int i = first; i < argc; ++i)
  {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0)
      return Status::Error("argument '" + a + "' is not of the form key=value.");
    const std::string name = a.substr(0, eq);
    const Key* key = nullptr;
    for (const Key& k : keys)
      if (k.name == name)
        key = &k;
    if (!key)
    {
      std::vector<std::string> names;
      for (const Key& k : keys)
        if (!k.hidden)
          names.push_back(k.name);
      std::sort(names.begin(), names.end());
      return Status::Error("unknown argument '" + name + "' (" + owner + " takes " + joined(names) +
                           ").");
    }
    if (Values.count(name))
      return Status::Error("argument '" + name + "' is given twice.");
    Values[name] = a.substr(eq + 1);
    if (Status s = check(*key, Values[name]); !s)
      return s;
  }
  return Status::Ok();
}

const Key& Arguments::find(const std::string& name, std::initializer_list<Kind> kinds) const
{
  if (!Table)
    internalError("'" + name + "' read before the command line was parsed");
  for (const Key& k : *Table)
    if (k.name == name)
    {
      for (Kind kind : kinds)
        if (k.kind == kind)
          return k;
      internalError("'" + name + "' is read as another kind than its table's");
    }
  internalError("'" + name + "' is read but not in the table");
}

double Arguments::number(const std::string& name) const
{
  const Key& k = find(name, {Kind::Number, Kind::Integer});
  if (k.computed)
    internalError("'" + name + "' has a computed default: give it");
  const auto it = Values.find(name);
  double v = 0;
  if (!toNumber(it == Values.end() ? k.fallback : it->second, v))
    internalError("'" + name + "' has no default");
  return v;
}

double Arguments::number(const std::string& name, double fallback) const
{
  const Key& k = find(name, {Kind::Number, Kind::Integer});
  if (!k.computed)
    internalError("'" + name + "' has its default in the table");
  const auto it = Values.find(name);
  if (it == Values.end())
    return fallback;
  double v = 0;
  toNumber(it->second, v);
  return v;
}

int Arguments::integer(const std::string& name) const
{
  find(name, {Kind::Integer});
  return static_cast<int>(number(name));
}

int Arguments::integer(const std::string& name, int fallback) const
{
  find(name, {Kind::Integer});
  return static_cast<int>(number(name, fallback));
}

std::vector<double> Arguments::list(const std::string& name) const
{
  const Key& k = find(name, {Kind::List});
  const auto it = Values.find(name);
  std::vector<double> out;
  for (const std::string& item : split(it == Values.end() ? k.fallback : it->second))
  {
    double v = 0;
    if (!toNumber(item, v))
      internalError("'" + name + "' has a bad default");
    out.push_back(v);
  }
  return out;
}

std::string Arguments::text(const std::string& name) const
{
  const Key& k = find(name, {Kind::Text, Kind::Choice, Kind::Model});
  const auto it = Values.find(name);
  return it == Values.end() ? k.fallback : it->second;
}

std::string Arguments::written(const std::string& name) const
{
  const Key& k =
      find(name, {Kind::Integer, Kind::Number, Kind::List, Kind::Text, Kind::Choice, Kind::Model});
  const auto it = Values.find(name);
  return it == Values.end() ? k.fallback : it->second;
}

ModelType Arguments::model(const std::string& name) const
{
  find(name, {Kind::Model});
  ModelType type = ModelType::SuperHelix;
  if (Status s = parseModel(text(name), name + "=", type); !s)
    internalError(s.message());
  return type;
}

namespace
{
std::string shown(const Key& k)
{
  if (!k.fallback.empty())
    return k.fallback;
  if (!k.shownAs.empty())
    return k.shownAs;
  if (k.kind == Kind::Choice)
    return joined(k.choices);
  return "";
}
} // namespace

std::string usageLine(const Keys& keys, std::size_t indent, std::size_t width)
{
  std::string out, line;
  for (const Key& k : keys)
  {
    if (k.hidden)
      continue;
    const std::string item = "[" + k.name + "=" + shown(k) + "]";
    if (!line.empty() && indent + line.size() + 1 + item.size() > width)
    {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
    }
    line += (line.empty() ? "" : " ") + item;
  }
  return out + line;
}

void describe(std::ostream& out, const Keys& keys)
{
  for (const Key& k : keys)
  {
    if (k.hidden)
      continue;
    std::string what;
    switch (k.kind)
    {
    case Kind::Integer:
      what = "whole number in " + range(k);
      break;
    case Kind::Number:
      what = "number in " + range(k);
      break;
    case Kind::List:
      what = "numbers in " + range(k) + ", comma-separated";
      break;
    case Kind::Text:
      what = "text";
      break;
    case Kind::Choice:
      what = "one of " + joined(k.choices);
      break;
    case Kind::Model:
      what = "one of " + modelNames() + (k.choices.empty() ? "" : ", " + joined(k.choices));
      break;
    }
    out << "  " << k.name << "=" << shown(k) << "\n      " << what;
    if (!k.help.empty())
      out << "; " << k.help;
    out << "\n";
  }
}

} // namespace hair::tools
