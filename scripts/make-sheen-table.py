#!/usr/bin/python3
"""Writes shaders/shared/sheen_albedo.glsl: the directional albedo E of the
sheen lobe of KHR_materials_sheen (shaders/shared/materials/sheen.glsl),

    E(mu_o, r) = integral over the hemisphere of f_sheen(wo, wi) cos(theta_i) dwi,

for a white sheen colour, on a grid of SHEEN_TABLE_SIZE cosines mu_o = i / (N - 1)
by SHEEN_TABLE_SIZE roughnesses r = j / (N - 1) (r below SHEEN_MIN_ROUGHNESS
is evaluated at it, as the kernels clamp it). The layer's albedo scaling
reads it (the extension's "sheenAlbedoScaling").

The integral is a product Gauss-Legendre rule in (cos(theta_i), phi_i),
symmetric in phi; the script integrates twice, the second time with twice
the nodes, and refuses to write a table whose two results differ by more
than 1e-4 anywhere.

Needs numpy (Debian: python3-numpy). Run from the repository root:
    /usr/bin/python3 scripts/make-sheen-table.py
"""
import numpy as np

N = 32
MIN_ROUGHNESS = 0.07
MIN_COS = 1e-3  # the first cosine: the lobe's limit at grazing wo


def sheen_l(x, a):
    t = (1.0 - a) ** 2
    fa = 21.5473 + (25.3245 - 21.5473) * t
    fb = 3.82987 + (3.32435 - 3.82987) * t
    fc = 0.19823 + (0.16801 - 0.19823) * t
    fd = -1.97760 + (-1.27393 + 1.97760) * t
    fe = -4.32054 + (-4.85967 + 4.32054) * t
    return fa / (1.0 + fb * np.power(x, fc)) + fd * x + fe


def sheen_lambda(c, a):
    return np.where(c < 0.5, np.exp(sheen_l(c, a)), np.exp(2.0 * sheen_l(0.5, a) - sheen_l(1.0 - c, a)))


def albedo(mu_o, r, n_theta, n_phi):
    a = r * r
    # Gauss-Legendre nodes on cos(theta_i) in (0, 1) and phi in (0, pi).
    x, wx = np.polynomial.legendre.leggauss(n_theta)
    mu = 0.5 * (x + 1.0)
    wmu = 0.5 * wx
    y, wy = np.polynomial.legendre.leggauss(n_phi)
    phi = 0.5 * np.pi * (y + 1.0)
    wphi = 0.5 * np.pi * wy
    MU, PHI = np.meshgrid(mu, phi, indexing="ij")
    W = np.outer(wmu, wphi) * 2.0  # phi over (0, pi), twice: the lobe is symmetric
    sin_i = np.sqrt(1.0 - MU * MU)
    wi = np.stack([sin_i * np.cos(PHI), sin_i * np.sin(PHI), MU], axis=-1)
    wo = np.array([np.sqrt(1.0 - mu_o * mu_o), 0.0, mu_o])
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    sin2 = np.clip(1.0 - h[..., 2] ** 2, 0.0, 1.0)
    d = (2.0 + 1.0 / a) * np.power(sin2, 0.5 / a) / (2.0 * np.pi)
    g = 1.0 / (1.0 + sheen_lambda(mu_o, a) + sheen_lambda(MU, a))
    f_cos = d * g / (4.0 * mu_o)  # f cos(theta_i): the 1 / cos(theta_i) cancels
    return float(np.sum(f_cos * W))


def table(n_theta, n_phi):
    t = np.zeros((N, N))
    for j in range(N):
        r = max(j / (N - 1), MIN_ROUGHNESS)
        for i in range(N):
            t[j, i] = albedo(max(i / (N - 1), MIN_COS), r, n_theta, n_phi)
    return t


def main():
    coarse = table(256, 128)
    fine = table(512, 256)
    err = np.max(np.abs(coarse - fine))
    if err > 1e-4:
        raise SystemExit("make-sheen-table.py: the quadrature has not converged (%.2e apart)" % err)
    lines = []
    for j in range(N):
        row = ", ".join("%.6ff" % v for v in fine[j])
        lines.append("    " + row + ("," if j < N - 1 else ""))
    out = """// sheen_albedo.glsl — written by scripts/make-sheen-table.py; do not edit.
// The directional albedo E(cos_o, r) of the sheen lobe (materials/sheen.glsl)
// for a white sheen colour: SHEEN_TABLE_SIZE roughnesses r = j / (N - 1)
// (rows) by SHEEN_TABLE_SIZE cosines cos_o = i / (N - 1) (columns), r below
// SHEEN_MIN_ROUGHNESS taken at it. Quadrature error below %.0e.
//
// The kernels read the table from the float tables (bindings.glsl), which
// the host fills from this array: a constant array in GLSL would be copied
// into every invocation, which lavapipe compiles for minutes.
#ifndef WP_SHEEN_ALBEDO_GLSL
#define WP_SHEEN_ALBEDO_GLSL

#define SHEEN_TABLE_SIZE %d
#define SHEEN_MIN_ROUGHNESS %.2ff

#ifdef __cplusplus
WP_TABLE(SHEEN_ALBEDO, %d)
%s
WP_TABLE_END
#endif

#endif  // WP_SHEEN_ALBEDO_GLSL
""" % (max(err, 1e-7), N, MIN_ROUGHNESS, N * N, "\n".join(lines))
    with open("shaders/shared/sheen_albedo.glsl", "w") as f:
        f.write(out)
    print("sheen_albedo.glsl: max |E| %.4f, quadrature change %.2e" % (fine.max(), err))


if __name__ == "__main__":
    main()
