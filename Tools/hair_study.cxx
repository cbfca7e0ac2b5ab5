// hair_study: the numerics of the ready-made studies of issue 6 and after, run from Core
// through its public API and written as CSV (or as a state file), for Scripts/study_*.py to
// plot. One study per file in Tools/studies/, each with its table of keys; this file only
// dispatches:
//
//   hair_study <study> out=<file> [key=value ...]   runs a study
//   hair_study <study> help                         its keys: defaults, ranges, meaning
//   hair_study help                                 every study's keys
//   hair_study                                      the usage (every study, one line each)
//
// Every study is described in docs/study-*.md. Bad input: a message on stderr naming the
// argument and what to do, exit status 2; a failed computation: exit status 1.
#include "studies/Studies.h"

#include <iostream>

using namespace hair::tools;

std::vector<Study> hair::tools::studies()
{
  return {convergenceStudy(),   bucklingStudy(), releaseStudy(),  sceneStudy(), integratorStudy(),
          workprecisionStudy(), orderStudy(),    accuracyStudy(), clumpStudy(), demoStudy(),
          oscillationStudy(),   pendulumStudy(), hairhairStudy()};
}

namespace
{

int usage(const std::vector<Study>& all)
{
  std::string names;
  for (const Study& s : all)
    names += (names.empty() ? "" : "|") + s.name;
  std::cerr << "usage: hair_study <" << names << "> out=<file> [key=value ...]\n"
            << "       hair_study <study> help (its keys, their ranges and meaning)\n";
  for (const Study& s : all)
  {
    const std::size_t indent = 16;
    std::string head = "  " + s.name;
    head += std::string(head.size() < indent ? indent - head.size() : 1, ' ');
    std::cerr << head << usageLine(s.keys, indent) << "\n";
  }
  return 2;
}

void help(const Study& s)
{
  std::cout << "hair_study " << s.name << ": " << s.summary << ".\n";
  describe(std::cout, s.keys);
}

} // namespace

int main(int argc, char** argv)
{
  const std::vector<Study> all = studies();
  if (argc < 2)
    return usage(all);
  const std::string name = argv[1];
  if (name == "help" && argc == 2)
  {
    for (const Study& s : all)
      help(s);
    return 0;
  }
  const auto it =
      std::find_if(all.begin(), all.end(), [&](const Study& s) { return s.name == name; });
  if (it == all.end())
  {
    std::cerr << "hair_study: unknown study '" << name << "'.\n";
    return usage(all);
  }
  if (argc == 3 && std::string(argv[2]) == "help")
  {
    help(*it);
    return 0;
  }
  Arguments args;
  if (hair::Status s = args.parse(argc, argv, 2, it->keys); !s)
  {
    std::cerr << "hair_study " << name << ": " << s.message() << "\n";
    return 2;
  }
  return it->run(args);
}
