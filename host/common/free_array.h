// Frees a vector's storage now (clear() keeps the capacity): for the host copies of arrays the
// device holds (gpu/gpu_tracer.h, render/wavefront_renderer.h).
#pragma once

#include <vector>

namespace hrpp {

template <class T>
void free_array(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

}  // namespace hrpp
