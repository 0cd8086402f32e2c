// PNG output (io/include/locus/io/write_png.hpp) with stb_image_write.
#include "locus/io/write_png.hpp"

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "locus/io/atomic_file_write.hpp"
#include "locus/error.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace locus {

namespace {

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* p = static_cast<const uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

}  // namespace

void write_png(const std::string& path, int width, int height, std::span<const uint8_t> rgb) {
  if (width <= 0 || height <= 0 || width > 65535 || height > 65535)
    fail(ErrorCode::BadUsage, path + ": image size " + std::to_string(width) + " x " + std::to_string(height) +
                                  " is not a valid PNG size");
  if (rgb.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 3)
    fail(ErrorCode::BadUsage, path + ": " + std::to_string(rgb.size()) + " bytes of pixels for a " +
                                  std::to_string(width) + " x " + std::to_string(height) + " RGB image");
  std::vector<uint8_t> encoded;
  if (!stbi_write_png_to_func(append, &encoded, width, height, 3, rgb.data(), width * 3))
    fail(ErrorCode::Internal, path + ": PNG encoding failed");
  io::write_file_atomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
  });
}

}  // namespace locus
