// Writes Hair Simulation's server-manager XML from its template (HairSimulation.xml.in) and
// the model registry (Core/simulation/ModelRegistry.h), so that the models' values and labels
// and which properties each model shows have one home, the registry:
//   <ModelEntries/>                     the Model enumeration's entries, one per model;
//   <ModelDecorator reads="<group>"/>   a visibility decorator showing the property when the
//                                       chosen model reads <group> (ModelEntry::reads).
// Every other line is copied as it is.
//   hair_simulation_xml <template> <output>
// Exit status 1 with a message naming the line for a group no model reads or an unknown one.
#include "simulation/ModelRegistry.h"

#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace
{

std::string generic(const std::string& indent, int value)
{
  return indent +
         "<PropertyWidgetDecorator type=\"GenericDecorator\" mode=\"visibility\" "
         "property=\"Model\" value=\"" +
         std::to_string(value) + "\"/>\n";
}

/// The decorator showing a property for the models in `shown` (values), among `all`: none
/// for every model, one GenericDecorator for one, their "or" for more.
std::string decorator(const std::string& indent, const std::vector<int>& shown,
                      const std::vector<int>& all)
{
  if (shown.size() == all.size())
  {
    return indent + "<!-- every registered model reads it -->\n";
  }
  if (shown.size() == 1)
  {
    return generic(indent, shown[0]);
  }
  std::string s = indent + "<PropertyWidgetDecorator type=\"CompositeDecorator\">\n" + indent +
                  "  <Expression type=\"or\">\n";
  for (int v : shown)
  {
    s += generic(indent + "    ", v);
  }
  return s + indent + "  </Expression>\n" + indent + "</PropertyWidgetDecorator>\n";
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 3)
  {
    std::cerr << "usage: hair_simulation_xml <template> <output>\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in)
  {
    std::cerr << "hair_simulation_xml: cannot read the template " << argv[1] << "\n";
    return 1;
  }
  std::vector<int> all;
  for (const hair::ModelEntry& e : hair::registeredModels())
  {
    all.push_back(static_cast<int>(e.type));
  }
  const std::regex entries(R"re(^(\s*)<ModelEntries/>\s*$)re");
  const std::regex reads(R"re(^(\s*)<ModelDecorator reads="([A-Za-z]+)"/>\s*$)re");
  std::ostringstream out;
  std::string line;
  int number = 0;
  while (std::getline(in, line))
  {
    ++number;
    std::smatch m;
    if (std::regex_match(line, m, entries))
    {
      for (const hair::ModelEntry& e : hair::registeredModels())
      {
        out << m[1] << "<Entry value=\"" << static_cast<int>(e.type) << "\" text=\"" << e.label
            << "\"/>\n";
      }
      continue;
    }
    if (!std::regex_match(line, m, reads))
    {
      out << line << "\n";
      continue;
    }
    const std::string group = m[2];
    unsigned flag = 0;
    std::string known;
    for (const hair::ModelReadsName& n : hair::modelReadsNames())
    {
      known += (known.empty() ? "" : ", ") + std::string(n.name);
      if (group == n.name)
      {
        flag = n.group;
      }
    }
    if (!flag)
    {
      std::cerr << argv[1] << ":" << number << ": the group '" << group
                << "' is not one the registry knows: use one of " << known << ".\n";
      return 1;
    }
    std::vector<int> shown;
    for (const hair::ModelEntry& e : hair::registeredModels())
    {
      if (e.reads & flag)
      {
        shown.push_back(static_cast<int>(e.type));
      }
    }
    if (shown.empty())
    {
      std::cerr << argv[1] << ":" << number << ": no registered model reads '" << group
                << "': its properties would never show; remove them or register a model "
                   "that reads them.\n";
      return 1;
    }
    out << decorator(m[1], shown, all);
  }
  // Written only when it changes, so that the plugin is not rebuilt for nothing.
  std::ifstream old(argv[2]);
  std::ostringstream previous;
  previous << old.rdbuf();
  if (old && previous.str() == out.str())
  {
    return 0;
  }
  std::ofstream file(argv[2]);
  file << out.str();
  if (!file)
  {
    std::cerr << "hair_simulation_xml: cannot write " << argv[2] << "\n";
    return 1;
  }
  return 0;
}
