// The options of `plucker vo` (the sliding window and the image front end) and their YAML file
// (`plucker vo --config FILE.yaml`). One row per key in vo_config.cc: the dotted key, a one-line
// doc and the member it sets. Defaults: the library's, except on images (ImageVoConfig), where
// the speed settings measured on the KITTI clip apply (README, "Real images: the KITTI clip").
#pragma once

#include <string>
#include <vector>

#include "plucker/odometry/monocular_odometry.h"

namespace plucker {
namespace app {

// The options of plucker vo are the pipeline's (odometry/monocular_odometry.h).
using VoConfig = odometry::MonocularOdometryOptions;

// The defaults for a features folder (the library's, new lines at 5 deg) and for images: new
// lines at 10 deg, a poses-only prior, 200 point tracks 20 px apart, the 60 longest segments
// detected at half resolution, 3 flow samples per segment, keyframes at 20 px of parallax or
// under 20 % tracked.
VoConfig FeaturesVoConfig();
VoConfig ImageVoConfig();

// The keys, in table order, with their docs ("key: doc").
std::vector<std::string> VoConfigKeys();

// Applies a YAML mapping (nested groups or dotted keys) to *config. Keys left out keep their
// value. Throws std::runtime_error naming `name` (the file) and the key for an unknown key, a
// value of the wrong type or out of range, and for YAML that does not parse.
void ApplyVoConfigYaml(const std::string& text, const std::string& name, VoConfig* config);
void LoadVoConfig(const std::string& path, VoConfig* config);

}  // namespace app
}  // namespace plucker
