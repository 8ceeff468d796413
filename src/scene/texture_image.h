// texture_image.h — image files for textures and environment maps, decoded to
// linear RGB floats: PNG / JPEG / BMP / TGA (sRGB, decoded) and HDR through
// stb_image, OpenEXR through tinyexr.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wp {

struct LinearImage {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;  // row by row, top row first
};

// Throws InputError naming the file and the decoder's reason.
LinearImage load_linear_image(const std::string& path);

// sRGB transfer function, decoded (IEC 61966-2-1).
float srgb_to_linear(float c);

}  // namespace wp
