// Returning the heap's free pages to the system between the phases of a long
// computation (defined in core/src/host_allocator.cpp, beside the host
// allocator's hooks it reads).
#pragma once

namespace locus {

// Hands the free pages the C library's heap keeps back to the system
// (glibc's malloc_trim) when no host allocator is set (locus_set_allocator);
// with one, and off glibc, nothing. For the points where a long computation
// has just freed large buffers: the heap keeps what it freed resident
// otherwise (a 416k-vertex remesh peaked ~50 MB of RSS above its heap). Costs
// the page faults of using those pages again.
void release_free_memory() noexcept;

}  // namespace locus
