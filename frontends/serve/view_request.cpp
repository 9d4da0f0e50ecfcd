#include "frontends/serve/view_request.h"

#include "sim/core/input_error.h"

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pp5::view_request {

[[noreturn]] void refuse(const std::string& field, const std::string& reason) {
    throw InputError(kRequest, field, reason);
}

void only_keys(const nlohmann::json& object, const std::string& field, const std::set<std::string>& allowed) {
    if (!object.is_object()) refuse(field, "expected an object");
    for (const auto& [key, value] : object.items()) {
        if (allowed.count(key) == 0) {
            std::string names;
            for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
            refuse(field.empty() ? key : field + "." + key, "unknown field (expected one of " + names + ")");
        }
    }
}

double number(const nlohmann::json& value, const std::string& field, double low, double high) {
    if (!value.is_number()) refuse(field, "expected a number");
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < low || v > high) refuse(field, fmt::format("must lie in [{}, {}]", low, high));
    return v;
}

namespace {

glm::vec3 vector3(const nlohmann::json& value, const std::string& field, double low, double high) {
    if (!value.is_array() || value.size() != 3) refuse(field, "expected three numbers [x, y, z]");
    glm::vec3 v;
    for (int i = 0; i < 3; ++i)
        v[i] =
            static_cast<float>(number(value[static_cast<std::size_t>(i)], fmt::format("{}[{}]", field, i), low, high));
    return v;
}

// [{"direction": [x, y, z], "intensity": s}, ...]: the lights that stay put while the key light moves.
std::vector<StationaryLight> stationary_lights(const nlohmann::json& value) {
    if (!value.is_array())
        refuse("light.stationary", "expected a list of {\"direction\": [x, y, z], \"intensity\": s}");
    if (value.size() > kMaxStationaryLights)
        refuse("light.stationary", fmt::format("at most {} stationary lights", kMaxStationaryLights));
    std::vector<StationaryLight> lights;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string field = fmt::format("light.stationary[{}]", i);
        only_keys(value[i], field, {"direction", "intensity"});
        if (!value[i].contains("direction")) refuse(field + ".direction", "is missing");
        StationaryLight light;
        light.direction = vector3(value[i]["direction"], field + ".direction", -1e3, 1e3);
        if (glm::length(light.direction) < 1e-6f)
            refuse(field + ".direction", "a direction towards the light cannot be zero");
        light.direction = glm::normalize(light.direction);
        if (value[i].contains("intensity"))
            light.intensity =
                static_cast<float>(number(value[i]["intensity"], field + ".intensity", 0.0, kMaxLightIntensity));
        lights.push_back(light);
    }
    return lights;
}

}  // namespace

void read_camera_change(const nlohmann::json& c, CameraSpec& camera) {
    only_keys(c, "camera", {"azimuth", "elevation", "zoom"});
    if (c.contains("azimuth"))
        camera.azimuth_degrees =
            static_cast<float>(std::remainder(number(c["azimuth"], "camera.azimuth", -1e6, 1e6), 360.0));
    if (c.contains("elevation"))
        camera.elevation_degrees = static_cast<float>(number(c["elevation"], "camera.elevation", -89.0, 89.0));
    if (c.contains("zoom")) camera.zoom = static_cast<float>(number(c["zoom"], "camera.zoom", 0.1, 20.0));
}

void read_light_change(const nlohmann::json& l, PhongLighting& lighting) {
    only_keys(l, "light", {"direction", "headlight", "stationary"});
    if (l.contains("headlight")) {
        if (!l["headlight"].is_boolean()) refuse("light.headlight", "expected true or false");
        lighting.light_follows_camera = l["headlight"].get<bool>();
    }
    if (l.contains("direction")) {
        const glm::vec3 d = vector3(l["direction"], "light.direction", -1e3, 1e3);
        if (glm::length(d) < 1e-6f) refuse("light.direction", "a direction towards the light cannot be zero");
        lighting.light_direction = glm::normalize(d);
        if (!l.contains("headlight")) lighting.light_follows_camera = false;
    }
    if (l.contains("stationary")) lighting.stationary_lights = stationary_lights(l["stationary"]);
}

std::optional<RegionOfInterest> read_region_change(const nlohmann::json& r,
                                                   const std::optional<RegionOfInterest>& current,
                                                   glm::ivec3 voxel_dims) {
    if (r.is_null()) return std::nullopt;
    only_keys(r, "region", {"shape", "center", "half_size", "scale_inside", "scale_outside", "transition", "cap"});
    const glm::vec3 dims(voxel_dims);
    RegionOfInterest region = current.value_or(RegionOfInterest{});
    if (!current) {
        region.center = 0.5f * (dims - 1.0f);
        region.half_size = glm::vec3(0.15f * std::min({dims.x, dims.y, dims.z}));
        region.scale_inside = 0.0f;
        region.transition = 2.0f;
    }
    if (r.contains("shape")) {
        if (r["shape"] == "box") region.shape = RegionOfInterest::Shape::Box;
        else if (r["shape"] == "ellipsoid") region.shape = RegionOfInterest::Shape::Ellipsoid;
        else refuse("region.shape", "must be \"box\" or \"ellipsoid\"");
    }
    const double reach = 2.0 * std::max({dims.x, dims.y, dims.z});
    if (r.contains("center")) region.center = vector3(r["center"], "region.center", -reach, reach);
    if (r.contains("half_size")) region.half_size = vector3(r["half_size"], "region.half_size", 0.5, reach);
    if (r.contains("scale_inside"))
        region.scale_inside = static_cast<float>(number(r["scale_inside"], "region.scale_inside", 0.0, 16.0));
    if (r.contains("scale_outside"))
        region.scale_outside = static_cast<float>(number(r["scale_outside"], "region.scale_outside", 0.0, 16.0));
    if (r.contains("transition")) {
        region.transition = static_cast<float>(number(r["transition"], "region.transition", 0.0, 100.0));
        if (region.transition > 0.0f && region.transition < 0.01f)
            refuse("region.transition", "is 0 (a hard edge) or at least 0.01 voxels");
    }
    if (r.contains("cap")) {
        if (!r["cap"].is_boolean()) refuse("region.cap", "expected true or false");
        region.cap = r["cap"].get<bool>();
    }
    validate_region(region, kRequest, "region");
    return region;
}

}  // namespace pp5::view_request
