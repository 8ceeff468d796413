#include "util/fault.h"

#include <atomic>
#include <cstdlib>
#include <sstream>
#include <string>

#include "util/error.h"

namespace wp::fault {

namespace {

struct Faults {
  uint64_t lostAt = 0;       // device-lost@submit:N (0: none)
  uint64_t allocAt = 0;      // oom@alloc:N
  uint64_t memoryBytes = 0;  // oom@bytes:N
  uint64_t writeAt = 0;      // enospc@write:N
  std::atomic<uint64_t> submits{0}, allocations{0}, held{0}, writes{0};
};

// Throws InputError for a value that names no fault: a test that meant to
// inject one must not pass without it.
Faults* parse(const char* spec) {
  if (!spec || !*spec) return nullptr;
  auto* f = new Faults();  // lives as long as the process
  std::istringstream in(spec);
  for (std::string item; std::getline(in, item, ',');) {
    const size_t colon = item.rfind(':');
    const std::string what = item.substr(0, colon == std::string::npos ? 0 : colon);
    char* end = nullptr;
    const unsigned long long n = colon == std::string::npos ? 0 : std::strtoull(item.c_str() + colon + 1, &end, 10);
    const bool number = end && *end == '\0' && end != item.c_str() + colon + 1 && n > 0;
    uint64_t* slot = what == "device-lost@submit" ? &f->lostAt
                     : what == "oom@alloc"        ? &f->allocAt
                     : what == "oom@bytes"        ? &f->memoryBytes
                     : what == "enospc@write"     ? &f->writeAt
                                                  : nullptr;
    if (!slot || !number) {
      delete f;
      throw InputError("WAVEPATH_FAULT: \"" + item + "\" is not a fault (device-lost@submit:N, oom@alloc:N, oom@bytes:N or enospc@write:N, N > 0)");
    }
    *slot = n;
  }
  return f;
}

std::atomic<Faults*>& current() {
  static std::atomic<Faults*> f{parse(std::getenv("WAVEPATH_FAULT"))};
  return f;
}

Faults* faults() {
  return current().load(std::memory_order_acquire);
}

}  // namespace

bool device_lost_at_submit() {
  Faults* f = faults();
  return f && f->lostAt && ++f->submits == f->lostAt;
}

bool device_memory_exhausted(uint64_t bytes) {
  Faults* f = faults();
  if (!f) return false;
  if (f->allocAt && ++f->allocations == f->allocAt) return true;
  if (!f->memoryBytes) return false;
  if (f->held.fetch_add(bytes) + bytes <= f->memoryBytes) return false;
  f->held -= bytes;
  return true;
}

void device_memory_freed(uint64_t bytes) {
  Faults* f = faults();
  if (!f || !f->memoryBytes) return;
  // Not below zero: a buffer made before inject() replaced the faults was never counted.
  uint64_t held = f->held.load();
  while (!f->held.compare_exchange_weak(held, held > bytes ? held - bytes : 0)) {
  }
}

uint64_t device_memory_limit() {
  Faults* f = faults();
  return f ? f->memoryBytes : 0;
}

bool disk_full_at_write() {
  Faults* f = faults();
  return f && f->writeAt && ++f->writes == f->writeAt;
}

uint64_t device_memory_held() {
  Faults* f = faults();
  return f ? f->held.load() : 0;
}

void inject(const char* spec) {
  current().store(parse(spec), std::memory_order_release);  // the faults before leak: a test's few bytes
}

}  // namespace wp::fault
