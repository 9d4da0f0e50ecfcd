#pragma once
// Internal to scene/scenario: the polygons a scenario scan-converts into its volume, [[polygons]] given
// by their vertices and the triangles of [[meshes]] read from OBJ files.

#include "scene/render/polygon.h"
#include "sim/core/toml_table.h"

#include <filesystem>
#include <vector>

namespace pp5 {

// Appends the polygons of `top`'s polygons and meshes arrays, each checked (validate_polygon);
// throws InputError naming the scenario file and the field. Mesh paths are relative to the scenario.
void read_scenario_polygons(TomlTable& top, const std::filesystem::path& scenario_file,
                            std::vector<PolygonSpec>& polygons);

}  // namespace pp5
