#pragma once
// A scenario: what to render and how, read from a TOML file under traces/. It names the dataset,
// the classification, the shading, the camera, the image, and a sequence of frames, each of which
// changes some of those settings relative to the frame before (Levoy's animation sequences).
// Every field is checked when the file is read; a bad one is an InputError naming the file, the
// field and the reason. The file format is documented in traces/README.md.

#include "scene/render/camera.h"
#include "scene/render/classification.h"
#include "scene/render/polygon.h"
#include "scene/render/region_of_interest.h"
#include "scene/render/resampling_order.h"
#include "scene/render/shading.h"
#include "scene/volume/volume.h"

#include <glm/vec3.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pp5 {

struct DatasetSpec {
    enum class Source { Packaged, File, Phantom, Raw };
    Source source = Source::Phantom;
    std::string name;        // packaged name, phantom name, or file path (absolute)
    int phantom_size = 128;  // n of an n^3 phantom
    glm::ivec3 raw_dims{0};  // Raw only
    ScalarType raw_type = ScalarType::UInt8;
    bool raw_big_endian = false;
    std::size_t raw_header_bytes = 0;
    glm::vec3 raw_spacing{1.0f};
    std::optional<glm::ivec3> resample_to;

    // The volume's size when the scenario alone says it (resampled, or raw), before anything is read.
    std::optional<glm::ivec3> known_dims() const {
        if (resample_to) return resample_to;
        if (source == Source::Raw) return raw_dims;
        return std::nullopt;
    }
};

// The camera as a user describes it: an orbit about the volume's centre.
struct CameraSpec {
    Projection projection = Projection::Parallel;
    glm::vec3 view_from{0.0f, 1.0f, 0.0f};  // direction from the volume's centre towards the eye at azimuth 0
    glm::vec3 up{0.0f, 0.0f, 1.0f};
    float azimuth_degrees = 0.0f;      // turn about `up`
    float elevation_degrees = 0.0f;    // tilt towards `up`
    float distance = 3.0f;             // eye distance in bounding-sphere radii
    float zoom = 1.0f;                 // >1 magnifies
    std::optional<float> fov_degrees;  // perspective; default fits the bounding sphere

    // The camera for a volume whose bounding sphere has this centre and radius (world units).
    Camera camera_for(glm::vec3 center, float radius) const;
};

struct ImageSpec {
    int width = 512;
    int height = 512;
    glm::vec3 background{0.0f};
    float sample_step = 1.0f;           // voxels between samples along a ray
    float termination_opacity = 0.95f;  // early ray termination; 1 disables
    ResamplingOrder resampling = ResamplingOrder::ShadeThenInterpolate;
};

// The full state of one frame, and what changed since the previous one.
struct FrameSpec {
    std::string label;
    CameraSpec camera;
    PhongLighting lighting;
    Classification classification;
    ColorMap colors;
    bool camera_changed = true;
    bool lighting_changed = true;
    bool classification_changed = true;
    std::optional<RegionOfInterest> region;  // the volume-of-interest tool, when in use
    bool region_changed = false;
};

struct Scenario {
    std::filesystem::path file;
    std::string name;
    std::string description;
    std::string kernel = "levoy";  // which algorithm renders the frames: a name in kernels/registry
    DatasetSpec dataset;
    ImageSpec image;
    std::vector<FrameSpec> frames;  // at least one
    // Polygons scan-converted into the volume (voxel coordinates): [[polygons]] and the triangles of
    // [[meshes]] (OBJ files).
    std::vector<PolygonSpec> polygons;
};

Scenario load_scenario(const std::filesystem::path& path);
// A scenario from TOML text in memory, as if read from `path` (which errors name, and relative dataset
// and mesh paths start from).
Scenario load_scenario_text(const std::string& text, const std::filesystem::path& path);

// Whether any frame lights the volume with stationary lights besides its key light.
bool has_stationary_lights(const Scenario& scenario);

// The scenario that `pp5sim render` runs when given none: the real MR head.
inline constexpr const char* kDefaultScenario = "mr-head";

// A path to an existing file, or the name of a shipped scenario (traces/scenarios/NAME.toml, or
// $PP5SIM_SCENARIOS/NAME.toml). Throws pp5::InputError naming the argument when neither exists.
std::filesystem::path resolve_scenario_file(const std::string& name_or_path);
// Every scenario file shipped in traces/scenarios/ (and in $PP5SIM_SCENARIOS).
std::vector<std::filesystem::path> shipped_scenario_files();
// Loads (and resamples) the dataset the scenario names; errors name the scenario file.
Volume load_dataset(const Scenario& scenario);

}  // namespace pp5
