#pragma once
// What Core asks of the machine it runs on.

namespace hair
{

/// The processors this process may run on.
int availableProcessors();
/// The machine's physical memory in bytes (infinite where the system cannot tell).
double physicalMemoryBytes();

} // namespace hair
