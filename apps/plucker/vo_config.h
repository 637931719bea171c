// The options of `plucker vo` (the sliding window, the image front end, the start) in one table
// (vo_config.cc, the mechanism of options_table.h): the YAML reader (`plucker vo --config
// FILE.yaml`), the flags that set the same options, config/vo_default.yaml and the table of
// docs/vo.md (`plucker config vo [--markdown]`). Defaults: the library's, except on images
// (ImageVoConfig), where the speed settings measured on the KITTI clip apply (docs/vo.md).
#pragma once

#include <string>
#include <vector>

#include "options_table.h"
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

const OptionsTable<VoConfig>& VoOptions();

// The options `plucker vo` and `plucker vio` share, by key ("window.size", "points.max_tracks",
// ...): one spelling, unit, doc and range in both tables. Throws std::logic_error for another key.
const OptionSpec& SharedVisualOption(const std::string& key);
// The keys of the shared bool options and their docs: "use_lines", "window.prior_on_poses_only".
extern const char* const kUseLinesDoc;
extern const char* const kPriorOnPosesOnlyDoc;
extern const char* const kRecheckTwoViewLinesDoc;  // "window.recheck_two_view_lines"

// "images: X" where the image default of `key` differs from the features one, else empty (the
// notes of the defaults file and the docs table).
std::string VoImageDefaultNote(const std::string& key);

// Applies a YAML mapping (nested groups or dotted keys) to *config. Keys left out keep their
// value. Throws std::runtime_error naming `name` (the file) and the key for an unknown or
// renamed key, a value of the wrong type or out of range, and for YAML that does not parse.
void ApplyVoConfigYaml(const std::string& text, const std::string& name, VoConfig* config);
void LoadVoConfig(const std::string& path, VoConfig* config);

}  // namespace app
}  // namespace plucker
