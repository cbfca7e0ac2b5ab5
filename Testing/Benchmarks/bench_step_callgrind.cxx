// Instructions per Super-Helix step, for callgrind (docs/benchmarks.md): the
// shaken strand of BM_Step (30 cm, N elements, head shaking ±30° at 3 Hz) stepped at 1/30 s,
// 30 steps from rest and then `steps` more, so that the total over 30 + steps steps divided by
// 30 + steps is one step's instruction count (start-up is ~0.5 % of 330 steps). Deterministic:
// the same executable gives the same count, unlike times on this shared machine.
//
//   valgrind --tool=callgrind --callgrind-out-file=cg.out \
//       build/Testing/bench_step_callgrind <preset 0-3> [steps=300] [N=10] [integrator=0|1]
//   callgrind_annotate cg.out | grep "PROGRAM TOTALS"      (÷ (30 + steps))
//
// integrator 1: the second-order step (StrandSpec::integrator = Midpoint); the steps it took
// first order go to stderr. It prints q after the last step with %a, so that two builds can
// be compared bit for bit.
#include "HeadShake.h"
#include "superhelix/SuperHelix.h"

#include <cstdio>
#include <cstdlib>

using namespace hair;

int main(int argc, char** argv)
{
  if (argc < 2)
  {
    std::fprintf(stderr,
                 "usage: bench_step_callgrind <preset 0-3> [steps=300] [N=10] [integrator=0|1]\n");
    return 2;
  }
  const int preset = std::atoi(argv[1]);
  const int steps = argc > 2 ? std::atoi(argv[2]) : 300;
  const int n = argc > 3 ? std::atoi(argv[3]) : 10;
  const int integrator = argc > 4 ? std::atoi(argv[4]) : 0;
  if (preset < 0 || preset > 3 || steps < 0 || n < 1 || integrator < 0 || integrator > 1)
  {
    std::fprintf(stderr, "bench_step_callgrind: preset must be 0…3, steps >= 0, N >= 1, "
                         "integrator 0 or 1\n");
    return 2;
  }
  StrandSpec spec = shakenStrand(HairType(preset), n);
  spec.integrator = integrator ? Integrator::Midpoint : Integrator::SemiImplicit;
  int firstOrder = 0;
  SuperHelix h;
  if (Status st = h.initialize(spec); !st)
  {
    std::fprintf(stderr, "bench_step_callgrind: %s\n", st.message().c_str());
    return 1;
  }
  for (int i = 0; i < 30 + steps; ++i)
  {
    if (Status st = h.step(1.0 / 30); !st)
    {
      std::fprintf(stderr, "bench_step_callgrind: %s\n", st.message().c_str());
      return 1;
    }
    firstOrder += h.lastFirstOrder();
  }
  std::fprintf(stderr, "steps taken first order: %d of %d\n", firstOrder, 30 + steps);
  for (int i = 0; i < h.q().size(); ++i)
    std::printf("%a\n", h.q()[i]);
  return 0;
}
