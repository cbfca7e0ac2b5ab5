// Fuzz target of the state-file reader (issue 24; docs/robustness.md): the input's bytes are
// written to a temporary file (HDF5 opens files by name; a real file also takes the reader's
// own path checks and its SWMR open, which the core driver would skip), opened with
// StateFileReader, every frame (up to 8) read, and each drawn as Hair State Reader draws it
// (drawGuides at 4 points per element), then its continuation read as a resumed run reads
// it. Refusals are the expected outcome of most inputs;
// a crash, a sanitizer report or a hang is a finding.
//
// Built two ways (Testing/Fuzz/CMakeLists.txt): with libFuzzer (clang, HAIR_BUILD_FUZZ) for
// Scripts/fuzz.sh, and with replay_main.cxx as replay_state_file, which CTest runs over the
// seed corpus and every input the fuzzer found a crash with (Testing/Fuzz/regressions/).
#include "io/StateFile.h"
#include "simulation/GuideDrawing.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
/// A file of this process's own in the temporary folder (TMPDIR, else /tmp).
const std::string& scratch()
{
  static const std::string path = []
  {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/hair-fuzz-" + std::to_string(getpid()) +
           ".h5";
  }();
  return path;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string& path = scratch();
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f)
    {
      std::perror(path.c_str());
      std::abort();
    }
    if (size > 0 && std::fwrite(data, 1, size, f) != size)
    {
      std::perror(path.c_str());
      std::abort();
    }
    std::fclose(f);
  }
  hair::StateFileReader reader;
  if (reader.open(path))
  {
    for (std::int64_t t = 0; t < reader.numberOfFrames() && t < 8; ++t)
    {
      hair::StateFrame frame;
      if (!reader.readFrame(t, frame))
      {
        continue;
      }
      hair::GuideDrawing drawing;
      (void)hair::drawGuides(reader.header(), frame, 4, 1, drawing);
    }
    // What a resumed run reads of it.
    hair::StateContinuation continuation;
    (void)reader.readContinuation(nullptr, continuation);
  }
  std::remove(path.c_str());
  return 0;
}
