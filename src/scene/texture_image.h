// texture_image.h — image files for textures and environment maps, decoded to
// linear RGB floats: PNG / JPEG / BMP / TGA (sRGB, decoded) and HDR through
// stb_image, OpenEXR through the OpenEXR library (image/exr.h).
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace wp {

struct LinearImage {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;  // row by row, top row first
  std::vector<float> alpha;       // opacity per pixel where the file has an alpha channel, else empty (opaque)
};

// What 8-bit values mean: sRGB-encoded colours (decoded to linear), linear
// data (glTF's metallic-roughness and normal textures), or linear data in the
// alpha channel, decoded to grey (glTF's sheen roughness and specular
// textures; opaque where the file has no alpha).
enum class ColorEncoding { Srgb, Linear, AlphaAsGrey };

// Throws InputError naming the file and the decoder's reason.
LinearImage load_linear_image(const std::string& path);

// The same for an image in memory (one a glTF file embeds); `name` names it
// in errors, `extension` (".tga") lets a TGA, which has no signature, decode.
LinearImage decode_linear_image(const std::vector<unsigned char>& bytes, const std::string& name, const std::string& extension,
                                ColorEncoding encoding);

// sRGB transfer function, decoded (IEC 61966-2-1).
float srgb_to_linear(float c);

}  // namespace wp
