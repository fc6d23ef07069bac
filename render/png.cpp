// PNG output through stb's image writer (Debian's libstb-dev).
#include "render/render.hpp"

#include <stdexcept>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace rb::render {

void write_png(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  if (rgb.size() != std::size_t(width) * std::size_t(height) * 3) throw std::invalid_argument("write_png: size mismatch");
  const std::vector<std::uint8_t> px = to_rgb8(rgb);
  if (!stbi_write_png(path.c_str(), width, height, 3, px.data(), width * 3))
    throw std::runtime_error(path + ": cannot write the PNG");
}

}  // namespace rb::render
