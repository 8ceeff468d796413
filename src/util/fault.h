// fault.h — faults injected for tests, through the environment variable
// WAVEPATH_FAULT (docs/partial-renders.md, "Faults"): a lost device, device
// memory exhausted, a full disk. Its value is a comma-separated list of
//
//   device-lost@submit:N   the Nth submission of samples (a pass of a tile)
//                          of the process fails with VK_ERROR_DEVICE_LOST,
//                          and the device with it
//   oom@alloc:N            the Nth device memory allocation fails with
//                          VK_ERROR_OUT_OF_DEVICE_MEMORY
//   oom@bytes:N            the device holds N bytes: every allocation that
//                          would take the memory held past N fails so
//   enospc@write:N         the Nth output file written fails with ENOSPC
//
// Checked where the host submits and allocates (gpu/vulkan_context.cpp) and
// in the one writer of files (write_atomically), never in the kernels. The
// variable is read once; unset, a check is a load and a branch.
#pragma once

#include <cstdint>

namespace wp::fault {

// Counts a submission of samples; true where it is to fail as a lost device.
bool device_lost_at_submit();
// Counts a device memory allocation of `bytes`; true where it is to fail
// as out of device memory. One that succeeds is held until
// device_memory_freed.
bool device_memory_exhausted(uint64_t bytes);
void device_memory_freed(uint64_t bytes);
// The device memory oom@bytes gives (0: none).
uint64_t device_memory_limit();
// Counts a file written; true where it is to fail as a full disk.
bool disk_full_at_write();

// For tests in one process: replaces the faults WAVEPATH_FAULT gave (or
// none, for nullptr) with `spec`'s, their counts from zero; and the device
// memory held since, where oom@bytes counts it.
void inject(const char* spec);
uint64_t device_memory_held();

}  // namespace wp::fault
