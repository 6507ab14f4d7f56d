// How much memory the machine has, and a check that a job's estimated need fits in it, so that an
// absurd size (a 2000^3 grid, a billion points) fails at once with a message saying why, instead
// of being killed for lack of memory half-way through.
#pragma once

#include <cstdint>
#include <string>

namespace frep {

// Physical memory in bytes (sysconf), or 0 when it cannot be told.
std::uint64_t physical_memory_bytes();

// Throws InputError without a file name (callers add theirs) when `count` items of `bytes_each`
// bytes (the product saturates instead of wrapping) exceed the physical
// memory: "<job> needs about N GB of memory, more than this machine's M GB: <advice>".
void require_memory(std::uint64_t count, std::uint64_t bytes_each, const std::string& job, const std::string& advice);

}  // namespace frep
