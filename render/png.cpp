// PNG output through stb's image writer (Debian's libstb-dev).
#include "render/render.hpp"

#include "core/output_file.hpp"

#include <stdexcept>
#include <string>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace rb::render {

void write_png(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  if (rgb.size() != std::size_t(width) * std::size_t(height) * 3) throw std::invalid_argument("write_png: size mismatch");
  const std::vector<std::uint8_t> px = to_rgb8(rgb);
  // Encoded in memory, then written by the output rule (core/output_file.hpp): a file whole or not
  // at all, a FIFO, a device or standard output ("-") as it is.
  std::string bytes;
  auto append = [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), std::size_t(size)); };
  if (!stbi_write_png_to_func(append, &bytes, width, height, 3, px.data(), width * 3))
    throw std::runtime_error(path + ": cannot encode the PNG");
  write_output(path, bytes);
}

}  // namespace rb::render
