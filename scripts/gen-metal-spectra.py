#!/usr/bin/python3
"""Writes shaders/shared/metal_spectra.glsl: the complex index of refraction
eta + i k of nine conductors (Au, Ag, Cu, Al, Cr, Ni, Ti, W, Pt) that the
spectral mode's conductor Fresnel term reads, resampled from the measured
tables below onto 360..830 nm every 10 nm (48 samples).

The tables are measurements, copied (never fitted, smoothed or extended)
from the refractiveindex.info database (M. N. Polyanskiy, public domain,
CC0; github.com/polyanskiy/refractiveindex.info-database, commit
ff11b5897ef0754b15d939d921eb6c745693cbd1, database/data/main/<metal>/nk/),
which gives wavelengths in micrometres: here they are in nm, the same
digits with the decimal point moved. Only each source's points from the
last at or below 360 nm to the first at or above 830 nm are kept (all nine
reach past both ends, so nothing is extrapolated). Resampling is linear in
wavelength between neighbouring source points; a wavelength outside a
source's points would take its nearest point's value.

Plain python3, no packages; the output is a function of this file alone:
    python3 scripts/gen-metal-spectra.py shaders/shared/metal_spectra.glsl
"""
import sys

SAMPLES = 48
START_NM = 360.0
STEP_NM = 10.0

# fmt: off
# Au, Ag, Cu: P. B. Johnson and R. W. Christy, "Optical constants of the noble
# metals", Phys. Rev. B 6, 4370-4379 (1972), doi:10.1103/PhysRevB.6.4370;
# evaporated films at room temperature. Transcribed from the database's
# Au|Ag|Cu/nk/Johnson.yml (the paper tabulates photon energies; the database's
# wavelengths are 1239.8 nm eV / E to four digits). Source range 187.9-1937 nm.
AU = [
    (354.2, 1.50, 1.866), (367.9, 1.48, 1.895), (381.5, 1.46, 1.933),
    (397.4, 1.47, 1.952), (413.3, 1.46, 1.958), (430.5, 1.45, 1.948),
    (450.9, 1.38, 1.914), (471.4, 1.31, 1.849), (495.9, 1.04, 1.833),
    (520.9, 0.62, 2.081), (548.6, 0.43, 2.455), (582.1, 0.29, 2.863),
    (616.8, 0.21, 3.272), (659.5, 0.14, 3.697), (704.5, 0.13, 4.103),
    (756.0, 0.14, 4.542), (821.1, 0.16, 5.083), (892.0, 0.17, 5.663),
]
AG = [
    (354.2, 0.10, 1.419), (367.9, 0.07, 1.657), (381.5, 0.05, 1.864),
    (397.4, 0.05, 2.070), (413.3, 0.05, 2.275), (430.5, 0.04, 2.462),
    (450.9, 0.04, 2.657), (471.4, 0.05, 2.869), (495.9, 0.05, 3.093),
    (520.9, 0.05, 3.324), (548.6, 0.06, 3.586), (582.1, 0.05, 3.858),
    (616.8, 0.06, 4.152), (659.5, 0.05, 4.483), (704.5, 0.04, 4.838),
    (756.0, 0.03, 5.242), (821.1, 0.04, 5.727), (892.0, 0.04, 6.312),
]
CU = [
    (354.2, 1.37, 1.916), (367.9, 1.36, 1.975), (381.5, 1.33, 2.045),
    (397.4, 1.32, 2.116), (413.3, 1.28, 2.207), (430.5, 1.25, 2.305),
    (450.9, 1.24, 2.397), (471.4, 1.25, 2.483), (495.9, 1.22, 2.564),
    (520.9, 1.18, 2.608), (548.6, 1.02, 2.577), (582.1, 0.70, 2.704),
    (616.8, 0.30, 3.205), (659.5, 0.22, 3.747), (704.5, 0.21, 4.205),
    (756.0, 0.24, 4.665), (821.1, 0.26, 5.180), (892.0, 0.30, 5.768),
]
# Al: A. D. Rakić, "Algorithm for the determination of intrinsic optical
# constants of metal films: application to aluminum", Appl. Opt. 34, 4755-4767
# (1995), doi:10.1364/AO.34.004755; the intrinsic constants of evaporated Al
# films from their measured optical and electron-energy-loss data (a
# Kramers-Kronig analysis made self-consistent). Transcribed from the
# database's Al/nk/Rakic.yml. Source range 0.124 nm - 200 um.
AL = [
    (326.28, 0.31474, 3.9165), (364.66, 0.39877, 4.3957), (413.28, 0.52135, 5.0008),
    (442.8, 0.60790, 5.3676), (476.87, 0.72780, 5.7781), (516.6, 0.87340, 6.2418),
    (563.57, 1.0728, 6.7839), (619.93, 1.3660, 7.4052), (652.25, 1.5724, 7.7354),
    (688.81, 1.8301, 8.0601), (729.32, 2.1606, 8.3565), (774.91, 2.6154, 8.4914),
    (794.78, 2.7675, 8.3866), (815.69, 2.7668, 8.2573), (837.74, 2.6945, 8.1878),
]
# Cr, Ni, Ti: P. B. Johnson and R. W. Christy, "Optical constants of transition
# metals: Ti, V, Cr, Mn, Fe, Co, Ni, and Pd", Phys. Rev. B 9, 5056-5070 (1974),
# doi:10.1103/PhysRevB.9.5056; evaporated films at room temperature.
# Transcribed from the database's Cr|Ni|Ti/nk/Johnson.yml (wavelengths to the
# nm, from the paper's photon energies). Source range 188-1937 nm.
CR = [
    (354.0, 1.84, 2.64), (368.0, 1.87, 2.69), (381.0, 1.92, 2.74),
    (397.0, 2.00, 2.83), (413.0, 2.08, 2.93), (431.0, 2.19, 3.04),
    (451.0, 2.33, 3.14), (471.0, 2.51, 3.24), (496.0, 2.75, 3.30),
    (521.0, 2.94, 3.33), (549.0, 3.18, 3.33), (582.0, 3.22, 3.30),
    (617.0, 3.17, 3.30), (659.0, 3.09, 3.34), (704.0, 3.05, 3.39),
    (756.0, 3.08, 3.42), (821.0, 3.20, 3.48), (892.0, 3.30, 3.52),
]
NI = [
    (354.0, 1.74, 2.32), (368.0, 1.70, 2.40), (381.0, 1.72, 2.48),
    (397.0, 1.72, 2.57), (413.0, 1.70, 2.69), (431.0, 1.71, 2.82),
    (451.0, 1.73, 2.95), (471.0, 1.78, 3.09), (496.0, 1.82, 3.25),
    (521.0, 1.85, 3.42), (549.0, 1.92, 3.61), (582.0, 1.96, 3.80),
    (617.0, 1.99, 4.02), (659.0, 1.99, 4.26), (704.0, 2.06, 4.50),
    (756.0, 2.13, 4.73), (821.0, 2.26, 4.97), (892.0, 2.40, 5.23),
]
TI = [
    (354.0, 1.82, 2.87), (368.0, 1.90, 2.90), (381.0, 1.99, 2.93),
    (397.0, 2.08, 2.95), (413.0, 2.14, 2.98), (431.0, 2.21, 3.01),
    (451.0, 2.27, 3.04), (471.0, 2.32, 3.10), (496.0, 2.36, 3.19),
    (521.0, 2.44, 3.30), (549.0, 2.54, 3.43), (582.0, 2.60, 3.58),
    (617.0, 2.67, 3.72), (659.0, 2.76, 3.84), (704.0, 2.86, 3.96),
    (756.0, 3.00, 4.01), (821.0, 3.21, 4.01), (892.0, 3.29, 3.96),
]
# W: J. H. Weaver, C. G. Olson and D. W. Lynch, "Optical properties of
# crystalline tungsten", Phys. Rev. B 12, 1293-1297 (1975),
# doi:10.1103/PhysRevB.12.1293; single crystal. The database's W/nk/Weaver.yml,
# transcribed here, read its points off the paper's figure (its note: "Data
# points extracted from a figure"). Source range 44.29 nm - 4.11 um.
W = [
    (357.6, 3.270, 2.705), (361.0, 3.323, 2.714), (366.2, 3.373, 2.677), (368.8, 3.401, 2.652),
    (372.0, 3.431, 2.621), (376.6, 3.454, 2.579), (379.0, 3.459, 2.556), (386.6, 3.458, 2.490),
    (391.2, 3.445, 2.460), (393.0, 3.438, 2.449), (400.2, 3.406, 2.415), (411.5, 3.379, 2.416),
    (411.8, 3.378, 2.416), (425.3, 3.346, 2.439), (429.8, 3.336, 2.450), (442.6, 3.317, 2.489),
    (448.7, 3.314, 2.511), (465.0, 3.325, 2.574), (469.4, 3.332, 2.591), (492.1, 3.380, 2.664),
    (493.7, 3.384, 2.668), (511.1, 3.433, 2.700), (529.8, 3.490, 2.716), (532.7, 3.497, 2.719),
    (548.9, 3.522, 2.739), (570.5, 3.524, 2.787), (573.9, 3.526, 2.794), (599.7, 3.557, 2.860),
    (602.4, 3.562, 2.866), (626.0, 3.607, 2.906), (626.8, 3.609, 2.907), (646.0, 3.657, 2.925),
    (652.4, 3.680, 2.937), (657.2, 3.697, 2.943), (671.2, 3.746, 2.937), (680.8, 3.797, 2.914),
    (684.9, 3.818, 2.904), (700.8, 3.871, 2.879), (706.1, 3.884, 2.869), (717.3, 3.896, 2.850),
    (731.4, 3.891, 2.828), (752.8, 3.862, 2.788), (754.9, 3.857, 2.784), (777.8, 3.789, 2.737),
    (781.7, 3.772, 2.731), (793.8, 3.705, 2.733), (795.8, 3.694, 2.735), (814.7, 3.596, 2.757),
    (832.7, 3.492, 2.801),
]
# Pt: A. Tselin, M. Pogodaeva, S. Levchenko, A. Kalmykov, K. Garbuzov,
# A. Smirnov and V. Drachev, "Exploring the dielectric function of platinum",
# Phys. Rev. B 110, 195130 (2024), doi:10.1103/PhysRevB.110.195130; an 80 nm
# e-beam evaporated film on quartz, by spectroscopic ellipsometry. Transcribed
# from the database's Pt/nk/Tselin.yml (numbers the authors gave it). Source
# range 190 nm - 3.5 um.
PT = [
    (358.894, 1.422, 3.053), (360.55, 1.426, 3.067), (362.206, 1.431, 3.080), (363.862, 1.435, 3.093),
    (365.518, 1.439, 3.107), (367.174, 1.444, 3.120), (368.829, 1.448, 3.134), (370.485, 1.453, 3.147),
    (372.141, 1.457, 3.160), (373.797, 1.461, 3.173), (375.453, 1.466, 3.186), (377.109, 1.470, 3.200),
    (378.764, 1.474, 3.213), (380.42, 1.479, 3.226), (382.076, 1.483, 3.239), (383.732, 1.487, 3.252),
    (385.388, 1.491, 3.265), (387.044, 1.496, 3.278), (388.699, 1.500, 3.291), (390.355, 1.504, 3.304),
    (392.011, 1.509, 3.317), (393.667, 1.513, 3.330), (395.323, 1.517, 3.343), (396.978, 1.521, 3.356),
    (398.634, 1.526, 3.369), (400.29, 1.530, 3.382), (401.946, 1.534, 3.394), (403.602, 1.539, 3.407),
    (405.258, 1.543, 3.420), (406.913, 1.547, 3.433), (408.569, 1.551, 3.446), (410.225, 1.556, 3.458),
    (411.881, 1.560, 3.471), (413.537, 1.564, 3.484), (415.193, 1.568, 3.497), (416.848, 1.573, 3.509),
    (418.504, 1.577, 3.522), (420.16, 1.581, 3.535), (421.816, 1.585, 3.547), (423.472, 1.590, 3.560),
    (425.128, 1.594, 3.573), (426.783, 1.598, 3.585), (428.439, 1.602, 3.598), (430.095, 1.606, 3.611),
    (431.751, 1.611, 3.623), (433.407, 1.615, 3.636), (435.063, 1.619, 3.648), (436.718, 1.623, 3.661),
    (438.374, 1.628, 3.674), (440.03, 1.632, 3.686), (441.686, 1.636, 3.699), (443.342, 1.640, 3.711),
    (444.998, 1.645, 3.724), (446.653, 1.649, 3.736), (448.309, 1.653, 3.749), (449.965, 1.657, 3.761),
    (451.621, 1.662, 3.774), (453.277, 1.666, 3.786), (454.932, 1.670, 3.799), (456.588, 1.675, 3.811),
    (458.244, 1.679, 3.824), (459.9, 1.683, 3.836), (461.556, 1.687, 3.848), (463.212, 1.692, 3.861),
    (464.867, 1.696, 3.873), (466.523, 1.700, 3.886), (468.179, 1.705, 3.898), (469.835, 1.709, 3.910),
    (471.491, 1.713, 3.923), (473.147, 1.718, 3.935), (474.802, 1.722, 3.948), (476.458, 1.726, 3.960),
    (478.114, 1.731, 3.972), (479.77, 1.735, 3.985), (481.426, 1.739, 3.997), (483.082, 1.744, 4.009),
    (484.737, 1.748, 4.022), (486.393, 1.752, 4.034), (488.049, 1.757, 4.046), (489.705, 1.761, 4.058),
    (491.361, 1.766, 4.071), (493.017, 1.770, 4.083), (494.672, 1.775, 4.095), (496.328, 1.779, 4.108),
    (497.984, 1.783, 4.120), (499.64, 1.788, 4.132), (501.296, 1.792, 4.144), (502.951, 1.797, 4.156),
    (504.607, 1.801, 4.169), (506.263, 1.806, 4.181), (507.919, 1.810, 4.193), (509.575, 1.815, 4.205),
    (511.231, 1.819, 4.217), (512.886, 1.824, 4.230), (514.542, 1.828, 4.242), (516.198, 1.833, 4.254),
    (517.854, 1.837, 4.266), (519.51, 1.842, 4.278), (521.166, 1.846, 4.290), (522.821, 1.851, 4.302),
    (524.477, 1.856, 4.314), (526.133, 1.860, 4.326), (527.789, 1.865, 4.339), (529.445, 1.869, 4.351),
    (531.101, 1.874, 4.363), (532.756, 1.879, 4.375), (534.412, 1.883, 4.387), (536.068, 1.888, 4.399),
    (537.724, 1.893, 4.411), (539.38, 1.897, 4.423), (541.036, 1.902, 4.435), (542.691, 1.907, 4.447),
    (544.347, 1.911, 4.459), (546.003, 1.916, 4.471), (547.659, 1.921, 4.482), (549.315, 1.926, 4.494),
    (550.97, 1.930, 4.506), (552.626, 1.935, 4.518), (554.282, 1.940, 4.530), (555.938, 1.945, 4.542),
    (557.594, 1.949, 4.554), (559.25, 1.954, 4.566), (560.905, 1.959, 4.578), (562.561, 1.964, 4.589),
    (564.217, 1.969, 4.601), (565.873, 1.974, 4.613), (567.529, 1.978, 4.625), (569.185, 1.983, 4.636),
    (570.84, 1.988, 4.648), (572.496, 1.993, 4.660), (574.152, 1.998, 4.672), (575.808, 2.003, 4.683),
    (577.464, 2.008, 4.695), (579.12, 2.013, 4.707), (580.775, 2.018, 4.718), (582.431, 2.023, 4.730),
    (584.087, 2.027, 4.742), (585.743, 2.032, 4.753), (587.399, 2.037, 4.765), (589.055, 2.042, 4.777),
    (590.71, 2.047, 4.788), (592.366, 2.052, 4.800), (594.022, 2.057, 4.811), (595.678, 2.062, 4.823),
    (597.334, 2.067, 4.834), (598.989, 2.072, 4.846), (600.645, 2.077, 4.857), (602.301, 2.082, 4.869),
    (603.957, 2.088, 4.880), (605.613, 2.093, 4.892), (607.269, 2.098, 4.903), (608.924, 2.103, 4.915),
    (610.58, 2.108, 4.926), (612.236, 2.113, 4.938), (613.892, 2.118, 4.949), (615.548, 2.123, 4.960),
    (617.204, 2.128, 4.972), (618.859, 2.133, 4.983), (620.515, 2.139, 4.994), (622.171, 2.144, 5.006),
    (623.827, 2.149, 5.017), (625.483, 2.154, 5.028), (627.139, 2.159, 5.039), (628.794, 2.164, 5.051),
    (630.45, 2.170, 5.062), (632.106, 2.175, 5.073), (633.762, 2.180, 5.084), (635.418, 2.185, 5.095),
    (637.074, 2.190, 5.107), (638.729, 2.196, 5.118), (640.385, 2.201, 5.129), (642.041, 2.206, 5.140),
    (643.697, 2.211, 5.151), (645.353, 2.217, 5.162), (647.008, 2.222, 5.173), (648.664, 2.227, 5.184),
    (650.32, 2.232, 5.195), (651.976, 2.238, 5.206), (653.632, 2.243, 5.217), (655.288, 2.248, 5.228),
    (656.943, 2.254, 5.239), (658.599, 2.259, 5.250), (660.255, 2.264, 5.261), (661.911, 2.269, 5.272),
    (663.567, 2.275, 5.283), (665.223, 2.280, 5.294), (666.878, 2.285, 5.305), (668.534, 2.291, 5.316),
    (670.19, 2.296, 5.326), (671.846, 2.301, 5.337), (673.502, 2.307, 5.348), (675.158, 2.312, 5.359),
    (676.813, 2.317, 5.370), (678.469, 2.323, 5.380), (680.125, 2.328, 5.391), (681.781, 2.334, 5.402),
    (683.437, 2.339, 5.413), (685.093, 2.344, 5.423), (686.748, 2.350, 5.434), (688.404, 2.355, 5.445),
    (690.06, 2.361, 5.455), (691.716, 2.366, 5.466), (693.372, 2.371, 5.477), (695.028, 2.377, 5.487),
    (696.683, 2.382, 5.498), (698.339, 2.388, 5.508), (699.995, 2.393, 5.519), (701.651, 2.398, 5.529),
    (703.307, 2.404, 5.540), (704.962, 2.409, 5.550), (706.618, 2.415, 5.561), (708.274, 2.420, 5.571),
    (709.93, 2.426, 5.582), (711.586, 2.431, 5.592), (713.242, 2.436, 5.603), (714.897, 2.442, 5.613),
    (716.553, 2.447, 5.624), (718.209, 2.453, 5.634), (719.865, 2.458, 5.644), (721.521, 2.464, 5.655),
    (723.177, 2.469, 5.665), (724.832, 2.475, 5.675), (726.488, 2.480, 5.686), (728.144, 2.486, 5.696),
    (729.8, 2.491, 5.706), (731.456, 2.497, 5.716), (733.112, 2.502, 5.727), (734.767, 2.508, 5.737),
    (736.423, 2.513, 5.747), (738.079, 2.519, 5.757), (739.735, 2.524, 5.767), (741.391, 2.530, 5.778),
    (743.047, 2.535, 5.788), (744.702, 2.541, 5.798), (746.358, 2.546, 5.808), (748.014, 2.552, 5.818),
    (749.67, 2.557, 5.828), (751.326, 2.563, 5.838), (752.981, 2.568, 5.848), (754.637, 2.574, 5.858),
    (756.293, 2.579, 5.868), (757.949, 2.585, 5.878), (759.605, 2.590, 5.888), (761.261, 2.596, 5.898),
    (762.916, 2.601, 5.908), (764.572, 2.607, 5.918), (766.228, 2.612, 5.928), (767.884, 2.618, 5.938),
    (769.54, 2.623, 5.948), (771.196, 2.629, 5.958), (772.851, 2.634, 5.968), (774.507, 2.640, 5.978),
    (776.163, 2.646, 5.988), (777.819, 2.651, 5.998), (779.475, 2.657, 6.007), (781.131, 2.662, 6.017),
    (782.786, 2.668, 6.027), (784.442, 2.673, 6.037), (786.098, 2.679, 6.047), (787.754, 2.684, 6.056),
    (789.41, 2.690, 6.066), (791.066, 2.695, 6.076), (792.721, 2.701, 6.086), (794.377, 2.707, 6.095),
    (796.033, 2.712, 6.105), (797.689, 2.718, 6.115), (799.345, 2.723, 6.124), (801.0, 2.729, 6.134),
    (802.656, 2.734, 6.144), (804.312, 2.740, 6.153), (805.968, 2.746, 6.163), (807.624, 2.751, 6.172),
    (809.28, 2.757, 6.182), (810.935, 2.762, 6.192), (812.591, 2.768, 6.201), (814.247, 2.773, 6.211),
    (815.903, 2.779, 6.220), (817.559, 2.785, 6.230), (819.215, 2.790, 6.239), (820.87, 2.796, 6.249),
    (822.526, 2.801, 6.258), (824.182, 2.807, 6.268), (825.838, 2.813, 6.277), (827.494, 2.818, 6.287),
    (829.15, 2.824, 6.296), (830.805, 2.829, 6.306),
]
# fmt: on

# (symbol, #define id, the source in a line, its points), in the ids' order.
METALS = [
    ("Au", "METAL_AU", "Johnson & Christy, Phys. Rev. B 6, 4370 (1972)", AU),
    ("Ag", "METAL_AG", "Johnson & Christy, Phys. Rev. B 6, 4370 (1972)", AG),
    ("Cu", "METAL_CU", "Johnson & Christy, Phys. Rev. B 6, 4370 (1972)", CU),
    ("Al", "METAL_AL", "Rakić, Appl. Opt. 34, 4755 (1995)", AL),
    ("Cr", "METAL_CR", "Johnson & Christy, Phys. Rev. B 9, 5056 (1974)", CR),
    ("Ni", "METAL_NI", "Johnson & Christy, Phys. Rev. B 9, 5056 (1974)", NI),
    ("Ti", "METAL_TI", "Johnson & Christy, Phys. Rev. B 9, 5056 (1974)", TI),
    ("W", "METAL_W", "Weaver, Olson & Lynch, Phys. Rev. B 12, 1293 (1975), read off its figure", W),
    ("Pt", "METAL_PT", "Tselin et al., Phys. Rev. B 110, 195130 (2024)", PT),
]


def wavelengths():
    return [START_NM + STEP_NM * i for i in range(SAMPLES)]


def check(symbol, points):
    if any(len(p) != 3 for p in points):
        raise SystemExit("gen-metal-spectra.py: %s: a point is not (nm, eta, k)" % symbol)
    for a, b in zip(points, points[1:]):
        if not a[0] < b[0]:
            raise SystemExit("gen-metal-spectra.py: %s: %g nm is not below %g nm" % (symbol, a[0], b[0]))
    if any(p[1] <= 0.0 or p[2] < 0.0 for p in points):
        raise SystemExit("gen-metal-spectra.py: %s: eta <= 0 or k < 0" % symbol)


def interpolate(points, lam):
    """(eta, k) at lam nm, linear in wavelength between the points around
    it; outside the points, the nearest point's value."""
    if lam <= points[0][0]:
        return points[0][1], points[0][2]
    if lam >= points[-1][0]:
        return points[-1][1], points[-1][2]
    for (l0, n0, k0), (l1, n1, k1) in zip(points, points[1:]):
        if l0 <= lam <= l1:
            t = (lam - l0) / (l1 - l0)
            return n0 + t * (n1 - n0), k0 + t * (k1 - k0)
    raise AssertionError("unreachable")


def literal(x):
    s = "%.6g" % x
    if "." not in s and "e" not in s:
        s += ".0"
    return s + "f"


def coverage_note():
    lo, hi = START_NM, START_NM + STEP_NM * (SAMPLES - 1)
    held = []
    for symbol, _, _, points in METALS:
        if points[0][0] > lo:
            held.append("%s below %g nm" % (symbol, points[0][0]))
        if points[-1][0] < hi:
            held.append("%s above %g nm" % (symbol, points[-1][0]))
    if not held:
        return ["Every source has points at or past both ends, so no value is held",
                "constant beyond a source's data."]
    return ["Past a source's data its nearest measured value is held constant: " + ", ".join(held) + "."]


def header():
    lines = [
        "// metal_spectra.glsl — written by scripts/gen-metal-spectra.py; do not edit.",
        "// Measured complex indices of refraction eta + i k (relative to vacuum) of",
        "// nine conductors, for the spectral mode's conductor Fresnel term:",
        "// METAL_SPECTRUM_SAMPLES samples per metal at 360, 370, ..., 830 nm",
        "// (METAL_SPECTRUM_STEP_NM apart), resampled linearly in wavelength from each",
        "// source's own wavelengths by the generator.",
    ]
    lines += ["// " + s for s in coverage_note()]
    lines += [
        "// Metal m's eta at sample i is METAL_ETA_K[(m * METAL_SPECTRUM_SAMPLES + i) * 2],",
        "// its k the float after it.",
        "//",
        "// Sources, transcribed from the refractiveindex.info database (public domain,",
        "// CC0; commit ff11b58, database/data/main/<metal>/nk/); the generator holds",
        "// the transcribed points, with the full references:",
    ]
    for symbol, _, source, _ in METALS:
        lines.append("//   %-3s %s" % (symbol, source))
    lines += [
        "//",
        "// The table is host only: wavepath-spectra copies it, and each metal's",
        "// linear sRGB projection, into the spectral tables the kernels read",
        "// (spectrum.glsl's SPECTRA_METALS). WP_METALS lists the metals by the names",
        "// scene files give them.",
        "#ifndef WP_METAL_SPECTRA_GLSL",
        "#define WP_METAL_SPECTRA_GLSL",
        "",
        "#define METAL_SPECTRUM_SAMPLES %d" % SAMPLES,
        "#define METAL_SPECTRUM_STEP_NM %s" % literal(STEP_NM),
        "",
    ]
    for m, (_, name, _, _) in enumerate(METALS):
        lines.append("#define %s %du" % (name, m))
    lines.append("#define WP_METALS(X) " + " ".join('X(%s, "%s")' % (name, symbol) for symbol, name, _, _ in METALS))
    lines += [
        "#define METAL_COUNT %du" % len(METALS),
        "",
        "#ifdef __cplusplus",
        "WP_TABLE(METAL_ETA_K, %d)  // METAL_COUNT * METAL_SPECTRUM_SAMPLES * 2" % (len(METALS) * SAMPLES * 2),
    ]
    values = []
    for symbol, _, _, points in METALS:
        row = []
        for lam in wavelengths():
            row += interpolate(points, lam)
        values.append((symbol, [literal(x) for x in row]))
    for m, (symbol, row) in enumerate(values):
        lines.append("    // %s" % symbol)
        for i in range(0, len(row), 8):
            last = m == len(values) - 1 and i + 8 >= len(row)
            lines.append("    " + ", ".join(row[i:i + 8]) + ("" if last else ","))
    lines += [
        "WP_TABLE_END",
        "#endif",
        "",
        "#endif  // WP_METAL_SPECTRA_GLSL",
    ]
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: python3 scripts/gen-metal-spectra.py shaders/shared/metal_spectra.glsl")
    for symbol, _, _, points in METALS:
        check(symbol, points)
    with open(sys.argv[1], "w", encoding="utf-8", newline="\n") as f:
        f.write(header())


if __name__ == "__main__":
    main()
