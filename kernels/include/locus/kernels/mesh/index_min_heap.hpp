// A binary min-heap of vertex ids keyed by dist[v], with each id's slot in
// pos[v] so a key can decrease in place: the priority queue of Dijkstra-style
// propagation (the patch grower's geodesic mode, the DEM baseline of thesis
// §6.8). One implementation, so the two settle tied vertices in the same order.
#pragma once
#include <cstdint>
#include <vector>

namespace locus {

// Restores the heap after heap[at]'s key decreased (or it was just appended).
template <class Heap>
inline void index_heap_sift_up(Heap& heap, const double* dist, int32_t* pos, int32_t at) {
  int32_t* h = heap.data();
  const int32_t v = h[at];
  const double key = dist[v];
  while (at > 0) {
    const int32_t up = (at - 1) >> 1;
    if (!(key < dist[h[up]])) break;
    h[at] = h[up];
    pos[h[at]] = at;
    at = up;
  }
  h[at] = v;
  pos[v] = at;
}

// Removes and returns the id with the smallest key (the heap must not be empty).
template <class Heap>
inline int32_t index_heap_pop_min(Heap& heap, const double* dist, int32_t* pos) {
  int32_t* h = heap.data();
  const int32_t top = h[0];
  const int32_t last = h[heap.size() - 1];
  heap.pop_back();
  const int32_t size = static_cast<int32_t>(heap.size());
  if (size > 0) {
    const double key = dist[last];
    int32_t at = 0;
    for (;;) {
      int32_t c = 2 * at + 1;
      if (c >= size) break;
      if (c + 1 < size && dist[h[c + 1]] < dist[h[c]]) ++c;
      if (!(dist[h[c]] < key)) break;
      h[at] = h[c];
      pos[h[at]] = at;
      at = c;
    }
    h[at] = last;
    pos[last] = at;
  }
  return top;
}

}  // namespace locus
