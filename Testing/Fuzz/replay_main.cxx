// Runs the fuzz target on files, as libFuzzer replays a corpus, without libFuzzer: a normal
// CTest test (fuzz.replay_state_file) over the seed corpus and the regression inputs, and a
// way to run one input under a debugger. Arguments: files or folders (every file in them).
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv)
{
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    struct stat info;
    if (::stat(argv[i], &info) != 0)
    {
      std::fprintf(stderr, "replay: %s does not exist\n", argv[i]);
      return 2;
    }
    if (!S_ISDIR(info.st_mode))
    {
      files.push_back(argv[i]);
      continue;
    }
    if (DIR* d = opendir(argv[i]))
    {
      while (dirent* e = readdir(d))
      {
        const std::string name = e->d_name;
        if (name != "." && name != ".." && name != "README.md")
        {
          files.push_back(std::string(argv[i]) + "/" + name);
        }
      }
      closedir(d);
    }
  }
  std::sort(files.begin(), files.end());
  for (const std::string& file : files)
  {
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::printf("replay: %s (%zu bytes)\n", file.c_str(), bytes.size());
    std::fflush(stdout);
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("replay: %zu inputs, none crashed\n", files.size());
  return files.empty() ? 1 : 0;
}
