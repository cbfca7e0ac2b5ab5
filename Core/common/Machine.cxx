#include "common/Machine.h"

#include <algorithm>
#include <limits>

#include <omp.h>
#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

namespace hair
{

int availableProcessors()
{
  return std::max(1, omp_get_num_procs());
}

double physicalMemoryBytes()
{
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  if (pages > 0 && size > 0)
  {
    return double(pages) * double(size);
  }
#endif
  return std::numeric_limits<double>::infinity();
}

} // namespace hair
