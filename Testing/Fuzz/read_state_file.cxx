// Reads one state file as Hair State Reader does and says what came of it, for
// Scripts/hostile_files.py (docs/robustness.md, "Hostile files at scale"), which runs it in a
// child process with a time limit on each damaged copy of a file:
//
//   read_state_file <file.h5>
//
// The file is opened with StateFileReader, then every frame is read whole and drawn as the
// reader draws it by default (drawGuides at 16 points per element), and read again as the two
// pieces a reader on 2 MPI ranks asks for, and last its continuation read as a resumed run
// reads it (whole and in the two pieces). Prints one line and exits with
//   0  "read whole: <file>: <frames> frames"
//   1  "refused: <message>" (the reader's message; a drawing's is prefixed with the file's
//      name, as Hair State Reader prefixes it)
// A crash or a hang is the caller's to see (a signal, a sanitizer report, the time limit).
#include "io/StateFile.h"
#include "simulation/GuideDrawing.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace
{
hair::Status readAll(const std::string& path, std::int64_t& frames)
{
  hair::StateFileReader reader;
  if (hair::Status s = reader.open(path); !s)
  {
    return s;
  }
  frames = reader.numberOfFrames();
  for (std::int64_t t = 0; t < frames; ++t)
  {
    hair::StateFrame frame;
    if (hair::Status s = reader.readFrame(t, frame); !s)
    {
      return s;
    }
    hair::GuideDrawing drawing;
    if (hair::Status s = hair::drawGuides(reader.header(), frame, 16, 1, drawing); !s)
    {
      return hair::Status::Error("'" + path + "': " + s.message());
    }
    for (int piece = 0; piece < 2; ++piece)
    {
      const std::vector<std::int64_t> mine = reader.pieceStrands(piece, 2);
      hair::StateFrame part;
      if (hair::Status s = reader.readPiece(t, mine, part); !s)
      {
        return s;
      }
      hair::GuideDrawing partDrawing;
      if (hair::Status s = hair::drawGuides(reader.header().piece(mine), part, 16, 1, partDrawing);
          !s)
      {
        return hair::Status::Error("'" + path + "': " + s.message());
      }
    }
  }
  // What a resumed run reads: the newest whole frame's continuation, whole and in pieces (a
  // file that keeps none, or a damaged one, says so: not a refusal of its frames).
  hair::StateContinuation continuation;
  (void)reader.readContinuation(nullptr, continuation);
  for (int piece = 0; piece < 2; ++piece)
  {
    const std::vector<std::int64_t> mine = reader.pieceStrands(piece, 2);
    (void)reader.readContinuation(&mine, continuation);
  }
  return hair::Status::Ok();
}
} // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: read_state_file <file.h5>\n");
    return 2;
  }
  const std::string path = argv[1];
  std::int64_t frames = 0;
  const hair::Status s = readAll(path, frames);
  if (!s)
  {
    std::printf("refused: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("read whole: %s: %lld frames\n", path.c_str(), static_cast<long long>(frames));
  return 0;
}
