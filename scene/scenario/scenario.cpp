#include "scene/scenario/scenario.h"

#include "scene/scenario/scenario_polygons.h"
#include "scene/scenario/scenario_values.h"

#include "scene/volume/datasets.h"
#include "scene/volume/host_memory.h"
#include "scene/volume/phantoms.h"
#include "scene/volume/resample.h"
#include "scene/volume/volume_io.h"
#include "sim/core/input_error.h"
#include "sim/core/named_file.h"
#include "sim/core/spelling.h"
#include "sim/core/toml_file.h"
#include "sim/core/toml_table.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <string_view>

namespace pp5 {
namespace {

using scenario_values::kHuge;
using scenario_values::small_integer;
using scenario_values::vec3;

// Where a refusal of an unknown key sends the user.
constexpr const char* kFormatHint = "see traces/README.md for the scenario format";

DatasetSpec read_dataset(TomlTable r, const std::filesystem::path& scenario_file) {
    DatasetSpec d;
    const auto packaged = r.text("packaged");
    const auto file = r.text("file");
    const auto phantom = r.text("phantom");
    if (int(packaged.has_value()) + int(file.has_value()) + int(phantom.has_value()) != 1)
        r.fail("", "name exactly one of packaged, file or phantom");
    if (packaged) {
        d.source = DatasetSpec::Source::Packaged;
        d.name = *packaged;
        if (!find_packaged_dataset(d.name)) {
            std::vector<std::string> known;
            for (const auto& p : packaged_datasets()) known.push_back(p.name);
            r.fail("packaged", fmt::format("unknown dataset \"{}\"{} (known: {})", d.name, did_you_mean(d.name, known),
                                           fmt::join(known, ", ")));
        }
    } else if (phantom) {
        d.source = DatasetSpec::Source::Phantom;
        d.name = *phantom;
        d.phantom_size = small_integer(r, "size", 2, 1024).value_or(d.phantom_size);
    } else {
        d.source = DatasetSpec::Source::File;
        std::filesystem::path p(*file);
        if (p.is_relative()) p = scenario_file.parent_path() / p;
        d.name = p.lexically_normal().string();
        if (r.has("raw")) {
            d.source = DatasetSpec::Source::Raw;
            TomlTable raw = r.sub("raw");
            const auto dims = vec3(raw, "dims", 1, 16384);
            if (!dims) raw.fail("dims", "required for a raw file, e.g. dims = [256, 256, 128]");
            d.raw_dims = glm::ivec3(*dims);
            if (glm::vec3(d.raw_dims) != *dims) raw.fail("dims", "must be whole numbers");
            const auto type = raw.text("type");
            if (!type) raw.fail("type", "required for a raw file, e.g. type = \"uint8\"");
            const auto parsed = parse_scalar_type(*type);
            if (!parsed) raw.fail("type", "unknown scalar type \"" + *type + "\"");
            d.raw_type = *parsed;
            d.raw_big_endian = raw.boolean("big_endian").value_or(false);
            d.raw_header_bytes = static_cast<std::size_t>(small_integer(raw, "header_bytes", 0, 1 << 30).value_or(0));
            d.raw_spacing = vec3(raw, "spacing", 1e-6, 1e6).value_or(glm::vec3(1.0f));
            raw.finish();
        }
    }
    if (const auto target = vec3(r, "resample", 2, 4096)) {
        if (glm::vec3(glm::ivec3(*target)) != *target) r.fail("resample", "must be whole numbers");
        d.resample_to = glm::ivec3(*target);
    }
    r.finish();
    return d;
}

void read_classification(TomlTable r, Classification& c, ColorMap& colors) {
    if (const auto kind = r.text("kind")) {
        if (*kind == "isovalue-contours") c.kind = ClassificationKind::IsovalueContours;
        else if (*kind == "region-boundaries") c.kind = ClassificationKind::RegionBoundaries;
        else if (*kind == "piecewise-linear") c.kind = ClassificationKind::PiecewiseLinear;
        else r.fail("kind", "\"" + *kind + "\" is not one of isovalue-contours, region-boundaries, piecewise-linear");
    }
    std::vector<IsovalueContour> contours;
    if (r.table_array("contours", [&](TomlTable& item) {
            IsovalueContour iso;
            const auto value = item.number("value", -kHuge, kHuge);
            if (!value) item.fail("value", "required");
            iso.value = static_cast<float>(*value);
            iso.opacity = static_cast<float>(item.number("opacity", 0, 1).value_or(1.0));
            iso.thickness = static_cast<float>(item.number("thickness", 1e-3, 1e3).value_or(1.0));
            contours.push_back(iso);
        }))
        c.contours = contours;
    std::vector<OpacityPoint> points;
    if (r.table_array("points", [&](TomlTable& item) {
            const auto value = item.number("value", -kHuge, kHuge);
            const auto opacity = item.number("opacity", 0, 1);
            if (!value || !opacity) item.fail(value ? "opacity" : "value", "required");
            if (!points.empty() && *value <= points.back().value)
                item.fail("value", "points must be in increasing order of value");
            points.push_back({static_cast<float>(*value), static_cast<float>(*opacity)});
        }))
        c.points = points;
    std::vector<ColorPoint> color_points;
    if (r.table_array("colors", [&](TomlTable& item) {
            const auto value = item.number("value", -kHuge, kHuge);
            const auto color = vec3(item, "color", 0, 1);
            if (!value || !color) item.fail(value ? "color" : "value", "required");
            if (!color_points.empty() && *value <= color_points.back().value)
                item.fail("value", "colors must be in increasing order of value");
            color_points.push_back({static_cast<float>(*value), *color});
        }))
        colors.points = color_points;
    r.finish();
    if (c.kind == ClassificationKind::IsovalueContours && c.contours.empty())
        r.fail("contours", "isovalue-contours needs at least one contour");
    if (c.kind != ClassificationKind::IsovalueContours && c.points.size() < 2)
        r.fail("points", "needs at least two points");
}

void read_shading(TomlTable r, PhongLighting& l) {
    l.ambient = static_cast<float>(r.number("ambient", 0, 10).value_or(l.ambient));
    l.diffuse = static_cast<float>(r.number("diffuse", 0, 10).value_or(l.diffuse));
    l.specular = static_cast<float>(r.number("specular", 0, 10).value_or(l.specular));
    l.shininess = static_cast<float>(r.number("shininess", 0, 1e4).value_or(l.shininess));
    if (const auto light = r.text("light")) {
        if (*light != "headlight") r.fail("light", "the only named light is \"headlight\"; else give light_direction");
        l.light_follows_camera = true;
    }
    if (const auto dir = vec3(r, "light_direction", -kHuge, kHuge)) {
        if (glm::length(*dir) == 0.0f) r.fail("light_direction", "must not be zero");
        l.light_direction = glm::normalize(*dir);
        l.light_follows_camera = false;
    }
    if (const auto k = r.node("depth_cue")) {
        const auto* a = k->as_array();
        const bool two_numbers = a && a->size() == 2 && (*a)[0].is_number() && (*a)[1].is_number();
        if (!two_numbers) r.fail("depth_cue", "expected [k1, k2]");
        l.depth_cue_k1 = static_cast<float>((*a)[0].value<double>().value());
        l.depth_cue_k2 = static_cast<float>((*a)[1].value<double>().value());
        if (!(l.depth_cue_k1 > 0.0f) || !(l.depth_cue_k2 >= 0.0f) || !std::isfinite(l.depth_cue_k1 + l.depth_cue_k2))
            r.fail("depth_cue", "needs k1 > 0 and k2 >= 0");
    }
    std::vector<StationaryLight> stationary;
    if (r.table_array("stationary_lights", [&](TomlTable& item) {
            const auto direction = vec3(item, "direction", -kHuge, kHuge);
            if (!direction) item.fail("direction", "required: [x, y, z] towards the light, world space");
            const float length = glm::length(*direction);
            if (!(length > 0.0f) || !std::isfinite(length)) item.fail("direction", "must be non-zero and finite");
            const auto intensity = item.number("intensity", 0, kMaxLightIntensity).value_or(1.0);
            stationary.push_back({glm::normalize(*direction), static_cast<float>(intensity)});
        })) {
        if (stationary.size() > kMaxStationaryLights)
            r.fail("stationary_lights",
                   fmt::format("at most {} lights (each adds its own Phong terms to every reshade)",
                               kMaxStationaryLights));
        l.stationary_lights = stationary;
    }
    r.finish();
}

void read_camera(TomlTable r, CameraSpec& c) {
    if (const auto p = r.text("projection")) {
        if (*p == "parallel") c.projection = Projection::Parallel;
        else if (*p == "perspective") c.projection = Projection::Perspective;
        else r.fail("projection", "\"" + *p + "\" is not parallel or perspective");
    }
    if (const auto v = vec3(r, "view_from", -kHuge, kHuge)) {
        if (glm::length(*v) == 0.0f) r.fail("view_from", "must not be zero");
        c.view_from = glm::normalize(*v);
    }
    if (const auto v = vec3(r, "up", -kHuge, kHuge)) {
        if (glm::length(*v) == 0.0f) r.fail("up", "must not be zero");
        c.up = glm::normalize(*v);
    }
    c.azimuth_degrees = static_cast<float>(r.number("azimuth", -1e6, 1e6).value_or(c.azimuth_degrees));
    c.elevation_degrees = static_cast<float>(r.number("elevation", -89.9, 89.9).value_or(c.elevation_degrees));
    c.distance = static_cast<float>(r.number("distance", 1.01, 1e4).value_or(c.distance));
    c.zoom = static_cast<float>(r.number("zoom", 1e-3, 1e3).value_or(c.zoom));
    if (const auto fov = r.number("fov_degrees", 0.1, 170)) c.fov_degrees = static_cast<float>(*fov);
    r.finish();
    if (std::abs(glm::dot(c.view_from, c.up)) > 0.999f) r.fail("up", "must not be parallel to view_from");
}

ImageSpec read_image(TomlTable r) {
    ImageSpec s;
    s.width = small_integer(r, "width", 1, 16384).value_or(s.width);
    s.height = small_integer(r, "height", 1, 16384).value_or(s.height);
    s.background = vec3(r, "background", 0, 1).value_or(s.background);
    s.sample_step = static_cast<float>(r.number("sample_step", 0.01, 16).value_or(s.sample_step));
    s.termination_opacity =
        static_cast<float>(r.number("termination_opacity", 0.01, 1).value_or(s.termination_opacity));
    if (const auto order = r.text("resampling")) {
        if (*order == "shade-then-interpolate") s.resampling = ResamplingOrder::ShadeThenInterpolate;
        else if (*order == "interpolate-then-shade") s.resampling = ResamplingOrder::InterpolateThenShade;
        else r.fail("resampling", "\"" + *order + "\" is not shade-then-interpolate or interpolate-then-shade");
    }
    r.finish();
    return s;
}

}  // namespace

Camera CameraSpec::camera_for(glm::vec3 center, float radius) const {
    // Turn view_from about `up` by the azimuth, then tilt it towards `up` by the elevation.
    const glm::vec3 level = glm::normalize(view_from - glm::dot(view_from, up) * up);
    const float az = glm::radians(azimuth_degrees);
    const float el = glm::radians(elevation_degrees);
    const glm::vec3 turned = std::cos(az) * level + std::sin(az) * glm::normalize(glm::cross(up, level));
    const glm::vec3 direction = std::cos(el) * turned + std::sin(el) * up;

    Camera camera;
    camera.projection = projection;
    camera.target = center;
    camera.eye = center + direction * (distance * radius);
    camera.up = up;
    camera.view_height = 2.0f * radius / zoom;
    const float fit = 2.0f * glm::degrees(std::asin(1.0f / distance));
    camera.fov_y_degrees = fov_degrees.value_or(fit / zoom);
    return camera;
}

// Where scenarios are found by name: $PP5SIM_SCENARIOS, then the source tree's traces/scenarios.
static NamedFileSearch scenario_search() {
#ifdef PP5_SCENARIOS_DIR
    const char* builtin = PP5_SCENARIOS_DIR;
#else
    const char* builtin = nullptr;
#endif
    return {"PP5SIM_SCENARIOS", builtin, "scenario", "traces/scenarios/*.toml"};
}

std::filesystem::path resolve_scenario_file(const std::string& name_or_path) {
    return resolve_named_file(name_or_path, scenario_search());
}

std::vector<std::filesystem::path> shipped_scenario_files() { return list_named_files(scenario_search()); }

void read_region(TomlTable r, std::optional<RegionOfInterest>& region) {
    RegionOfInterest g = region.value_or(RegionOfInterest{});
    if (const auto shape = r.text("shape")) {
        if (*shape == "box") g.shape = RegionOfInterest::Shape::Box;
        else if (*shape == "ellipsoid") g.shape = RegionOfInterest::Shape::Ellipsoid;
        else r.fail("shape", "must be \"box\" or \"ellipsoid\"");
    }
    g.center = vec3(r, "center", -kHuge, kHuge).value_or(g.center);
    g.half_size = vec3(r, "half_size", 1e-3, kHuge).value_or(g.half_size);
    g.rotation_degrees = vec3(r, "rotation", -3600, 3600).value_or(g.rotation_degrees);
    g.scale_inside = static_cast<float>(r.number("scale_inside", 0, 16).value_or(g.scale_inside));
    g.scale_outside = static_cast<float>(r.number("scale_outside", 0, 16).value_or(g.scale_outside));
    g.transition = static_cast<float>(r.number("transition", 0, 1000).value_or(g.transition));
    // The PPs measure the distance to the surface in 1/128 voxel; a ramp much narrower than that is
    // no ramp, and its slope would not fit their fields.
    constexpr float kNarrowest = 0.01f;
    if (g.transition > 0.0f && g.transition < kNarrowest)
        r.fail("transition",
               fmt::format("is {} voxels: give 0 for a hard edge, or at least {}", g.transition, kNarrowest));
    g.cap = r.boolean("cap").value_or(g.cap);
    if (g.cap && g.shape != RegionOfInterest::Shape::Box)
        r.fail("cap", "capping is for a box region (its faces give the caps' normals)");
    if (g.cap && !(g.transition > 0.0f))
        r.fail("cap", "capping recolours the transition zone: give the region a transition wider than 0");
    const bool off = !r.boolean("enabled").value_or(true);
    r.finish();
    region = off ? std::nullopt : std::optional<RegionOfInterest>(g);
}

namespace {
Scenario read_scenario(const toml::table& root, const std::filesystem::path& path);
}  // namespace

bool has_stationary_lights(const Scenario& scenario) {
    return std::any_of(scenario.frames.begin(), scenario.frames.end(),
                       [](const FrameSpec& frame) { return !frame.lighting.stationary_lights.empty(); });
}

Scenario load_scenario(const std::filesystem::path& path) { return read_scenario(read_toml_file(path.string()), path); }

Scenario load_scenario_text(const std::string& text, const std::filesystem::path& path) {
    return read_scenario(read_toml_text(text, path.string()), path);
}

namespace {

Scenario read_scenario(const toml::table& root, const std::filesystem::path& path) {
    const std::string file = path.string();
    TomlTable top(&root, "", file, kFormatHint);
    Scenario s;
    s.file = path;

    TomlTable meta = top.sub("scenario");
    s.name = meta.text("name").value_or(path.stem().string());
    s.description = meta.text("description").value_or("");
    // Checked against the registry when a run starts (this layer lies below the kernels).
    if (const auto kernel = meta.text("kernel")) s.kernel = *kernel;
    meta.finish();
    // It names the output folder, out/<name>.
    if (const std::string problem = output_name_problem(s.name); !problem.empty()) meta.fail("name", problem);

    if (!top.has("dataset")) top.fail("dataset", "required: a [dataset] table naming packaged, file or phantom");
    s.dataset = read_dataset(top.sub("dataset"), path);
    s.image = read_image(top.sub("image"));

    FrameSpec base;
    base.label = "frame";
    base.classification.contours = {IsovalueContour{}};
    if (!top.has("classification")) top.fail("classification", "required: how voxel values become opacity");
    read_classification(top.sub("classification"), base.classification, base.colors);
    read_shading(top.sub("shading"), base.lighting);
    read_camera(top.sub("camera"), base.camera);
    if (top.has("region")) read_region(top.sub("region"), base.region);

    read_scenario_polygons(top, path, s.polygons);

    // Each [[frames]] entry patches the state left by the frame before it.
    FrameSpec current = base;
    const bool listed = top.table_array("frames", [&](TomlTable& item) {
        FrameSpec next = current;
        next.label = item.text("label").value_or(fmt::format("frame {}", s.frames.size()));
        next.camera_changed = item.has("camera") || s.frames.empty();
        next.lighting_changed = item.has("shading") || s.frames.empty();
        next.classification_changed = item.has("classification") || s.frames.empty();
        next.region_changed = item.has("region") || s.frames.empty();
        if (item.has("region")) read_region(item.sub("region"), next.region);
        if (item.has("camera")) read_camera(item.sub("camera"), next.camera);
        if (item.has("shading")) read_shading(item.sub("shading"), next.lighting);
        if (item.has("classification"))
            read_classification(item.sub("classification"), next.classification, next.colors);
        s.frames.push_back(next);
        current = next;
    });
    if (!listed) s.frames.push_back(base);
    if (s.frames.empty()) top.fail("frames", "an empty list: give at least one frame, or leave frames out");
    if (s.frames.size() > 100000) top.fail("frames", "more than 100000 frames");
    top.finish();
    return s;
}

}  // namespace

Volume load_dataset(const Scenario& scenario) {
    const DatasetSpec& d = scenario.dataset;
    Volume volume;
    switch (d.source) {
        case DatasetSpec::Source::Packaged: volume = load_packaged_dataset(d.name); break;
        case DatasetSpec::Source::Phantom:
            check_volume_fits_host(scenario.file.string(), "dataset.size", glm::ivec3(d.phantom_size),
                                   ScalarType::UInt8);
            try {
                volume = make_phantom(d.name, d.phantom_size);
            } catch (const InputError& e) {
                throw InputError(scenario.file.string(), "dataset.phantom", e.reason());
            }
            break;
        case DatasetSpec::Source::File: volume = load_volume(d.name); break;
        case DatasetSpec::Source::Raw:
            volume = load_raw(d.name,
                              RawLayout{d.raw_dims, d.raw_type, d.raw_big_endian, d.raw_header_bytes, d.raw_spacing});
            break;
    }
    if (d.resample_to) {
        check_volume_fits_host(scenario.file.string(), "dataset.resample", *d.resample_to, ScalarType::Float32);
        volume = resample(volume, *d.resample_to);
    }
    // Rendering interpolates between neighbouring samples: every axis needs two.
    if (glm::any(glm::lessThan(volume.dims(), glm::ivec3(2))))
        throw InputError(scenario.file.string(), d.resample_to ? "dataset.resample" : "dataset",
                         fmt::format("the volume is {}x{}x{}; rendering needs at least two voxels along each axis",
                                     volume.dims().x, volume.dims().y, volume.dims().z));
    return volume;
}

}  // namespace pp5
