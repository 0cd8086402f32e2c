// Private random numbers for METIS calls.
//
// Debian's METIS draws from glibc rand()/srand(), one generator for the whole
// process: two METIS calls at once (the halves of a nested dissection, two
// Sessions) interleave draws and order differently from run to run. locus
// defines rand()/srand() itself: inside a MetisRandomScope they use a
// generator owned by the calling thread (METIS seeds it with srand at the
// start of every call, so each call is reproducible on its own); everywhere
// else they forward to the C library, so the host program sees no change.
#pragma once
#include <cstdint>
#include <mutex>

namespace locus {

// While alive, rand()/srand() on this thread use a private generator.
class MetisRandomScope {
 public:
  MetisRandomScope();
  ~MetisRandomScope();
  MetisRandomScope(const MetisRandomScope&) = delete;
  MetisRandomScope& operator=(const MetisRandomScope&) = delete;
  uint64_t draws() const { return draws_; }  // rand() calls taken from the private generator

  uint64_t state_ = 0;
  uint64_t draws_ = 0;

 private:
  MetisRandomScope* outer_ = nullptr;
};

// True when libmetis' rand()/srand() resolve to locus' definitions (probed once
// with a small METIS call). False when the dynamic linker bound them elsewhere
// (e.g. locus linked into a plugin loaded with RTLD_LOCAL): METIS calls must
// then be serialized.
bool metis_random_is_private();

// Held around every METIS call when the generator is not private.
std::mutex& metis_serial_mutex();

}  // namespace locus
