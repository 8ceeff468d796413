// rgb_to_spectrum.cpp — the RGB uplift's optimizer and table lookup
// (rgb_to_spectrum.h). The algorithm is Jakob and Hanika's (2019, the
// procedure of pbrt-v4's rgb2spec_opt): for each grid colour, Gauss-Newton
// steps on the three coefficients against the CIELAB difference between the
// target and the spectrum's colour, the Jacobian by finite differences,
// starting from the solution of the same chromaticity one brightness step
// closer to a fifth of the range, where spectra are easiest to find.
#include "render/rgb_to_spectrum.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "render/shader_cpp.h"

namespace wp {
namespace {

constexpr double kMinNm = SPECTRUM_MIN_NM, kMaxNm = SPECTRUM_MAX_NM;
constexpr int kSamples = CIE_D65_SAMPLES;  // 5 nm steps, D65's own samples

// What a reflectance spectrum's samples contribute to its XYZ under D65
// (trapezoid weights, D65, the matching functions; Y of a white reflector 1)
// and to its linear sRGB; the white reflector's XYZ. The matching functions'
// fit puts D65's white a little off sRGB's, so the RGB is balanced by
// per-channel gains that take the white reflector to (1, 1, 1) exactly (the
// film will apply them too).
struct Integration {
  std::array<glm::dvec3, kSamples> rgbWeight, xyzWeight;
  std::array<double, kSamples> unitLambda;  // the sample's wavelength mapped to [0, 1]
  glm::dvec3 white{0.0}, gains{0.0};
  double norm = 0.0;  // the sum of D65 times y bar (trapezoid weights)

  Integration() {
    shader::ShaderMath m;
    for (int i = 0; i < kSamples; ++i) {
      const double lambda = kMinNm + 5.0 * i;
      const double w = (i == 0 || i == kSamples - 1) ? 2.5 : 5.0;
      const glm::dvec3 bar(m.cie_xyz_bar(float(lambda)));
      xyzWeight[size_t(i)] = w * double(shader::ShaderMath::CIE_D65[i]) * bar;
      norm += xyzWeight[size_t(i)].y;
      unitLambda[size_t(i)] = (lambda - kMinNm) / (kMaxNm - kMinNm);
    }
    for (int i = 0; i < kSamples; ++i) {
      xyzWeight[size_t(i)] /= norm;
      white += xyzWeight[size_t(i)];
      // spectrum.glsl's xyz_to_linear_srgb, in double.
      const glm::dvec3 x = xyzWeight[size_t(i)];
      rgbWeight[size_t(i)] = WP_XYZ_TO_LINEAR_SRGB(glm::dvec3, x.x, x.y, x.z);
      gains += rgbWeight[size_t(i)];
    }
    for (glm::dvec3& w : rgbWeight) w /= gains;
  }
};

const Integration& integration() {
  static const Integration in;
  return in;
}

double sigmoid(double x) {
  if (std::isinf(x)) return x > 0.0 ? 1.0 : 0.0;
  return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x));
}

// CIELAB of an XYZ against the white reflector's.
glm::dvec3 lab(glm::dvec3 xyz, glm::dvec3 white) {
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  const double fx = f(xyz.x / white.x), fy = f(xyz.y / white.y), fz = f(xyz.z / white.z);
  return glm::dvec3(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
}

glm::dvec3 rgb_to_xyz(glm::dvec3 c) {
  return glm::dvec3(0.4124564 * c.x + 0.3575761 * c.y + 0.1804375 * c.z, 0.2126729 * c.x + 0.7151522 * c.y + 0.0721750 * c.z,
                    0.0193339 * c.x + 0.1191920 * c.y + 0.9503041 * c.z);
}

// The XYZ of the spectrum with coefficients c for the wavelength mapped to
// [0, 1] (the optimizer's variable: its coefficients stay of one size).
glm::dvec3 unit_spectrum_xyz(const glm::dvec3& c) {
  const Integration& in = integration();
  glm::dvec3 xyz(0.0);
  for (int i = 0; i < kSamples; ++i) {
    const double l = in.unitLambda[size_t(i)];
    xyz += sigmoid((c.x * l + c.y) * l + c.z) * in.xyzWeight[size_t(i)];
  }
  return xyz;
}

glm::dvec3 residual(const glm::dvec3& c, const glm::dvec3& targetLab) {
  return lab(unit_spectrum_xyz(c), integration().white) - targetLab;
}

// Gauss-Newton on c for the target rgb, from c's current value.
void solve(glm::dvec3& c, glm::dvec3 rgb) {
  const glm::dvec3 target = lab(rgb_to_xyz(rgb * integration().gains), integration().white);
  for (int iteration = 0; iteration < 15; ++iteration) {
    const glm::dvec3 r = residual(c, target);
    if (glm::dot(r, r) < 1e-12) return;
    glm::dmat3 jacobian;
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 lo = c, hi = c;
      lo[k] -= 1e-4;
      hi[k] += 1e-4;
      jacobian[k] = (residual(hi, target) - residual(lo, target)) / 2e-4;  // column k
    }
    if (std::fabs(glm::determinant(jacobian)) < 1e-15) return;
    c -= glm::inverse(jacobian) * r;
    // Keep the quadratic bounded, as the sigmoid saturates long before.
    const double largest = std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)});
    if (largest > 200.0) c *= 200.0 / largest;
  }
}

double smoothstep(double x) {
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace

glm::dvec3 spectrum_to_rgb(const std::function<double(double)>& s) {
  const Integration& in = integration();
  glm::dvec3 rgb(0.0);
  for (int i = 0; i < kSamples; ++i) rgb += s(kMinNm + 5.0 * i) * in.rgbWeight[size_t(i)];
  return rgb;
}

glm::dvec3 spectrum_to_rgb(glm::vec3 c) {
  shader::ShaderMath m;
  return spectrum_to_rgb([&](double lambda) { return double(m.sigmoid_polynomial(c, float(lambda))); });
}

RgbToSpectrumTable make_rgb_to_spectrum_table(int res) {
  RgbToSpectrumTable t;
  t.res = res;
  t.scale.resize(size_t(res));
  for (int k = 0; k < res; ++k) t.scale[size_t(k)] = float(smoothstep(smoothstep(double(k) / (res - 1))));
  t.coefficients.assign(size_t(3) * res * res * res * 3, 0.0f);
  const int start = res / 5;
  tbb::parallel_for(0, 3 * res, [&](int lj) {
    const int l = lj / res, j = lj % res;
    for (int i = 0; i < res; ++i) {
      const double x = double(i) / (res - 1), y = double(j) / (res - 1);
      auto store = [&](int k, const glm::dvec3& c) {
        float* out = &t.coefficients[((size_t(l * res + k) * res + size_t(j)) * res + size_t(i)) * 3];
        out[0] = float(c.x);
        out[1] = float(c.y);
        out[2] = float(c.z);
      };
      auto colour = [&](int k) {
        const double z = t.scale[size_t(k)];
        glm::dvec3 rgb;
        rgb[l] = z;
        rgb[(l + 1) % 3] = x * z;
        rgb[(l + 2) % 3] = y * z;
        return rgb;
      };
      glm::dvec3 c(0.0);
      for (int k = start; k < res; ++k) {
        solve(c, colour(k));
        store(k, c);
      }
      c = glm::dvec3(0.0);
      for (int k = start; k >= 0; --k) {
        solve(c, colour(k));
        store(k, c);
      }
    }
  });
  return t;
}

glm::dvec3 film_white_gains() {
  return integration().gains;
}

double d65_to_unit_luminance() {
  return double(CIE_Y_INTEGRAL) / integration().norm;
}

}  // namespace wp
