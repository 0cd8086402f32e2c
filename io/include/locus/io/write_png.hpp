// PNG output for previews: 8-bit RGB, via stb_image_write
// (Debian libstb-dev). The pixels are written to memory first, then to the
// file in one write, so a failure names the file and leaves no partial image
// under its name.
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace locus {

// rgb: width * height * 3 bytes, rows top to bottom. Error(BadUsage) for sizes
// that do not match or are not positive; Error(BadInput) when the file cannot
// be written.
void write_png(const std::string& path, int width, int height, std::span<const uint8_t> rgb);

}  // namespace locus
