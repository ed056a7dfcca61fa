// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the upper bounds on every size a file, parameter or stream can ask for.
 *
 * One place for them: the readers (mask, scene, frame settings, bundle, network
 * settings) and the blocks refuse anything larger with the bound in the message,
 * so a typo such as "targets": 2000000000 is an error, never an allocation without
 * limit, and N*M can never overflow an int.
 */
#ifndef INCLUDED_SEMS_LIMITS_H
#define INCLUDED_SEMS_LIMITS_H

namespace gr {
namespace sems {
namespace limits {

constexpr int max_symbols = 65536;          // N, OFDM symbols per frame
constexpr int max_subcarriers = 65536;      // M
constexpr long long max_grid = 1LL << 22;   // N*M resource elements per frame (4 194 304)
constexpr int max_targets = 256;            // targets per scene
constexpr int max_paths = 256;              // paths per target
constexpr int max_clutter_paths = 4096;     // static clutter scatterers per scene
constexpr int max_classes = 1024;           // classes of a classifier bundle or a random scene
constexpr int max_super_frames = 4096;      // frames of a super-frame mask (F), each with its own pilots
constexpr int max_track_frames = 1 << 20;   // frames of one track of a random scene (9.3 h of the paper's 32 ms frames)
constexpr int max_network_size = 1000000;   // any width/depth/count in the network settings
constexpr int max_template_frames = 1 << 20; // a spectral classifier's template bank (training frames)
constexpr long long max_template_values = 1LL << 28; // its frames x pilots (2 GiB of complex floats)
// Relative powers (targets, paths, scatterers) up to 10^30: 300 dB between the strongest and the
// weakest, and sums of up to 256 x 256 of them stay far from overflow (1e308 + 1e308 = inf
// would zero every normalised power).
constexpr double max_relative_power = 1e30;
// A link budget's largest SNR per resource element (its nearest, strongest target): 300 dB keeps
// a frame's values (single-precision floats) and their squares finite.
constexpr double max_link_snr_db = 300.0;
// Micro-motion (micro_motion.h): sizes of one target's scatterer model.
constexpr int max_rotors = 16;              // rotors of a rotor target
constexpr int max_blades = 16;              // blades per rotor
constexpr int max_wheels = 16;              // wheels of a wheeled target
constexpr int max_rim_points = 64;          // point scatterers per rim
constexpr int max_spokes = 64;              // spokes per wheel
constexpr int max_scatterers = 256;         // point scatterers of a `scatterers` target
constexpr int max_harmonics = 16;           // harmonics per point scatterer
// Arrays (array_geometry.h): elements of one kind (receive or transmit). 1024 receive streams
// are more than any flowgraph runs; a frame of the paper's 32 pilots then carries 32 768 values.
constexpr int max_array_elements = 1024;

} // namespace limits
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIMITS_H */
