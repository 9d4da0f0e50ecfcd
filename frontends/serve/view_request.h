#pragma once
// Internal to frontends/serve: what a browser tool's request asks of the view, read strictly. Every
// refusal is an InputError("request", field, reason), which the server answers with a 400 naming the
// field (docs/serve.md lists the requests).

#include "scene/render/region_of_interest.h"
#include "scene/render/shading.h"
#include "scene/scenario/scenario.h"

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <string>

namespace pp5::view_request {

inline constexpr const char* kRequest = "request";

[[noreturn]] void refuse(const std::string& field, const std::string& reason);
// Refuses a non-object, and any key of `object` (at `field`) not in `allowed`.
void only_keys(const nlohmann::json& object, const std::string& field, const std::set<std::string>& allowed);
double number(const nlohmann::json& value, const std::string& field, double low, double high);

// The camera a "camera" change leaves: azimuth (wrapped to a turn), elevation, zoom.
void read_camera_change(const nlohmann::json& change, CameraSpec& camera);
// The lights a "light" change leaves: a direction (which stops the headlight unless it says so),
// the headlight, the stationary lights.
void read_light_change(const nlohmann::json& change, PhongLighting& lighting);
// The region a "region" change leaves (null: none). A first region starts as a cut-away cube in the
// middle of a volume of `dims` voxels.
std::optional<RegionOfInterest> read_region_change(const nlohmann::json& change,
                                                   const std::optional<RegionOfInterest>& current, glm::ivec3 dims);

}  // namespace pp5::view_request
