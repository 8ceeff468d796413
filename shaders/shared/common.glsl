// common.glsl — the bridge that lets every file in shaders/shared/ compile twice:
// as GLSL 4.60 for the compute kernels, and as C++17 (with GLM) for the host and
// the CPU reference renderer. Shared code follows a few rules so both compilers
// accept it:
//   * no swizzles (GLM only has them behind a slow macro): write vec3(a.x, a.y, a.z);
//   * out / inout parameters are spelled OUT(T) / INOUT(T);
//   * constants are #defines or namespace-scope `const` (never inside functions
//     that C++ compiles as struct members);
//   * structs are vec4 / uvec4 / (vec3 + one 4-byte scalar) so std430 and C++ agree;
//     tests/test_layout.cpp checks that against the SPIR-V the kernels compile to.
#ifndef WP_COMMON_GLSL
#define WP_COMMON_GLSL

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
namespace wp::shader {
using namespace glm;
using uint = std::uint32_t;
}  // namespace wp::shader
#define OUT(T) T&
#define INOUT(T) T&
#else
#define OUT(T) out T
#define INOUT(T) inout T
#endif

// A constant table of n floats, written WP_TABLE(NAME, n) v0, v1, ... WP_TABLE_END
// (generated tables: sheen_albedo.glsl). In C++ it is a static member of the
// struct the shared code compiles into.
#ifdef __cplusplus
#define WP_TABLE(name, n) static constexpr float name[n] = {
#define WP_TABLE_END };
#else
#define WP_TABLE(name, n) const float name[n] = float[n](
#define WP_TABLE_END );
#endif

#define WP_PI 3.14159265358979323846f
#define WP_INV_PI 0.31830988618379067154f
// Rec. 709 luminance weights (sampling.glsl's illuminance; the host's default-sky rule).
#define LUMINANCE_R 0.2126f
#define LUMINANCE_G 0.7152f
#define LUMINANCE_B 0.0722f
#define WP_INF 3.402823466e+38f

// Spectrum: the type of the colours a path carries (its throughput, its
// radiance, a BSDF's value). The kernels are compiled twice (CMakeLists.txt):
// the RGB kernels' is vec3, red, green and blue; the spectral kernels'
// (WP_SPECTRUM4) is vec4, radiance at the path's four wavelengths
// (spectral.glsl), so an RGB render carries no fourth channel. C++, one
// compile for both modes, takes vec4, and in RGB leaves its w out of every
// sum (SPECTRUM_CHANNELS, colour.glsl). Records keep their colours in RGB.
#ifdef __cplusplus
namespace wp::shader {
using Spectrum = glm::vec4;
}
#define WP_SPECTRUM_W 1
#elif defined(WP_SPECTRUM4)
#define Spectrum vec4
#define WP_SPECTRUM_W 1
#else
#define Spectrum vec3
#endif
#define WP_INVALID 0xffffffffu

#endif  // WP_COMMON_GLSL
