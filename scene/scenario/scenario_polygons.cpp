#include "scene/scenario/scenario_polygons.h"

#include "scene/scenario/scenario_values.h"
#include "sim/core/input_error.h"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <charconv>
#include <climits>
#include <fstream>
#include <string>
#include <string_view>

namespace pp5 {

namespace {

using scenario_values::kHuge;
using scenario_values::vec3;

// A list of [x, y, z] points.
std::vector<glm::vec3> read_points(TomlTable& r, const std::string& key) {
    std::vector<glm::vec3> points;
    const toml::node* n = r.node(key);
    if (!n) return points;
    const auto* a = n->as_array();
    if (!a) r.fail(key, "expected an array of [x, y, z] points");
    for (std::size_t i = 0; i < a->size(); ++i) {
        const auto* p = a->get(i)->as_array();
        if (!p || p->size() != 3) r.fail(key, fmt::format("point {} is not [x, y, z]", i));
        glm::vec3 v{};
        for (int k = 0; k < 3; ++k) {
            const auto x = (*p)[static_cast<std::size_t>(k)].value<double>();
            if (!x) r.fail(key, fmt::format("point {} is not [x, y, z] numbers", i));
            v[k] = static_cast<float>(*x);
        }
        points.push_back(v);
    }
    return points;
}

// One colour for all vertices (color) or one each (colors); likewise opacity / opacities.
void read_vertex_attributes(TomlTable& item, PolygonSpec& p) {
    if (const auto c = vec3(item, "color", 0, 1)) p.colors = {*c};
    if (item.has("colors")) p.colors = read_points(item, "colors");
    if (p.colors.empty()) p.colors = {glm::vec3(1.0f)};
    if (const auto a = item.number("opacity", 0, 1)) p.opacities = {static_cast<float>(*a)};
    if (const auto* n = item.node("opacities")) {
        const auto* a = n->as_array();
        if (!a) item.fail("opacities", "expected an array of numbers");
        for (std::size_t i = 0; i < a->size(); ++i) {
            const auto x = (*a)[i].value<double>();
            if (!x) item.fail("opacities", "expected an array of numbers");
            p.opacities.push_back(static_cast<float>(*x));
        }
    }
    if (p.opacities.empty()) p.opacities = {1.0f};
}

// tinyobj reads an index too large for an int as some other index; such a file names no vertex we
// could have, so it is refused here, naming the line. Returns the line's problem, or empty.
std::string oversized_obj_index(std::string_view text) {
    std::size_t line_number = 0;
    for (std::size_t start = 0; start < text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        std::string_view line = text.substr(start, end - start);
        start = end + 1;
        ++line_number;
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos) continue;
        line.remove_prefix(first);
        if (line.size() < 2 || (line[0] != 'f' && line[0] != 'l' && line[0] != 'p') ||
            (line[1] != ' ' && line[1] != '\t'))
            continue;
        for (std::size_t at = 1; at < line.size();) {
            const std::size_t digits = line.find_first_of("+-0123456789", at);
            if (digits == std::string_view::npos) break;
            const std::size_t stop = std::min(line.find_first_not_of("+-0123456789", digits), line.size());
            long long value = 0;
            const std::string_view number = line.substr(digits, stop - digits);
            const auto [ptr, ec] =
                std::from_chars(number.data() + (number[0] == '+' ? 1 : 0), number.data() + number.size(), value);
            if (ec == std::errc::result_out_of_range || (ec == std::errc() && (value > INT_MAX || value < -INT_MAX)))
                return fmt::format("line {}: index {} is beyond any vertex a mesh can have", line_number, number);
            at = stop;
        }
    }
    return {};
}

// The triangles of an OBJ mesh, scaled then translated into voxel coordinates.
std::vector<PolygonSpec> read_mesh(TomlTable& item, const std::filesystem::path& scenario_file) {
    const auto file = item.text("file");
    if (!file) item.fail("file", "required: the mesh's .obj file, relative to the scenario");
    std::filesystem::path path(*file);
    if (path.is_relative()) path = scenario_file.parent_path() / path;
    const glm::vec3 scale = vec3(item, "scale", -kHuge, kHuge).value_or(glm::vec3(1.0f));
    const glm::vec3 translate = vec3(item, "translate", -kHuge, kHuge).value_or(glm::vec3(0.0f));
    PolygonSpec attributes;
    read_vertex_attributes(item, attributes);
    if (attributes.colors.size() != 1 || attributes.opacities.size() != 1)
        item.fail("colors", "a mesh takes one color and one opacity for all its triangles");
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    tinyobj::ObjReader reader;
    std::error_code status_error;  // a symlink loop is unreadable, not an exception
    const bool readable = std::filesystem::is_regular_file(path, status_error);
    std::string text;
    if (readable) {
        std::ifstream in(path, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (const std::string problem = oversized_obj_index(text); !problem.empty())
            item.fail("file", path.string() + ": " + problem);
    }
    if (!readable || !reader.ParseFromString(text, "", config)) {
        std::string why = reader.Error().empty() ? "cannot be read" : reader.Error();
        while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
        item.fail("file", path.string() + " is not a readable OBJ mesh: " + why);
    }
    const auto& vertices = reader.GetAttrib().vertices;
    std::vector<PolygonSpec> triangles;
    for (const auto& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
            PolygonSpec t = attributes;
            t.vertices.clear();
            for (std::size_t k = 0; k < 3; ++k) {
                const int v = indices[f + k].vertex_index;
                // In size_t: 3 v overflows an int for indices near INT_MAX.
                const std::size_t at = 3 * static_cast<std::size_t>(std::max(v, 0));
                if (v < 0 || at + 2 >= vertices.size())
                    item.fail("file", path.string() + ": a face refers to a vertex the file does not have");
                const glm::vec3 p(vertices[at], vertices[at + 1], vertices[at + 2]);
                t.vertices.push_back(p * scale + translate);
            }
            triangles.push_back(std::move(t));
        }
    }
    if (triangles.empty()) item.fail("file", path.string() + ": the mesh has no faces");
    return triangles;
}

}  // namespace

void read_scenario_polygons(TomlTable& top, const std::filesystem::path& scenario_file,
                            std::vector<PolygonSpec>& polygons) {
    const std::string file = scenario_file.string();
    top.table_array("polygons", [&](TomlTable& item) {
        PolygonSpec p;
        p.vertices = read_points(item, "vertices");
        read_vertex_attributes(item, p);
        validate_polygon(p, file, item.field(""));
        polygons.push_back(std::move(p));
    });
    top.table_array("meshes", [&](TomlTable& item) {
        for (PolygonSpec& t : read_mesh(item, scenario_file)) {
            validate_polygon(t, file, item.field(""));
            polygons.push_back(std::move(t));
        }
    });
}

}  // namespace pp5
