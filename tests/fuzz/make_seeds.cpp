// Writes each harness's seed corpus: small valid inputs of every kind, made here from the formats'
// definitions (tests/support/volume_files.h) or taken from the shipped text files, so that no binary
// input is kept in git. Usage: make_fuzz_seeds OUT_DIR SOURCE_DIR; writes OUT_DIR/<harness>/<seed>.
#include "tests/support/volume_files.h"

#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using pp5::test::Bytes;

namespace {

void write_plain(const fs::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

void write_gzipped(const fs::path& path, const Bytes& bytes) {
    gzFile gz = gzopen(path.c_str(), "wb");
    if (gz == nullptr ||
        gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size())) != static_cast<int>(bytes.size()) ||
        gzclose(gz) != Z_OK)
        throw std::runtime_error("cannot write " + path.string());
}

Bytes text(const std::string& s) { return pp5::test::text_bytes(s); }

template <class T>
Bytes ramp(int count, T step) {
    std::vector<T> values;
    for (int i = 0; i < count; ++i)
        values.push_back(static_cast<T>(static_cast<double>(i) * static_cast<double>(step)));
    return pp5::test::sample_bytes(values);
}

void nifti_seeds(const fs::path& dir) {
    pp5::test::NiftiSpec u8;
    u8.set_dims(3, 2, 2);
    write_plain(dir / "uint8.nii", pp5::test::nifti_bytes(u8, ramp<std::uint8_t>(12, 20)));
    write_gzipped(dir / "uint8.nii.gz", pp5::test::nifti_bytes(u8, ramp<std::uint8_t>(12, 20)));

    pp5::test::NiftiSpec i16 = u8;
    i16.datatype = 4;
    i16.bitpix = 16;
    i16.order = std::endian::big;
    i16.scl_slope = 2.0f;
    i16.scl_inter = -100.0f;
    i16.pixdim = {1, 0.5f, 0.75f, 2.0f, 1, 1, 1, 1};
    std::vector<std::int16_t> values;
    for (int i = 0; i < 12; ++i) values.push_back(static_cast<std::int16_t>(i * 300 - 1000));
    write_plain(dir / "int16-big-endian.nii",
                pp5::test::nifti_bytes(i16, pp5::test::sample_bytes(values, std::endian::big)));

    pp5::test::NiftiSpec f32 = u8;
    f32.datatype = 16;
    f32.bitpix = 32;
    f32.dim[0] = 4;  // a fourth dimension of 1
    write_plain(dir / "float32-4d.nii", pp5::test::nifti_bytes(f32, ramp<float>(12, 0.25f)));
}

void den_seeds(const fs::path& dir) {
    const glm::ivec3 dims{4, 3, 2};
    write_plain(dir / "little-endian.den", pp5::test::den_bytes(dims, ramp<std::uint8_t>(24, 10)));
    write_plain(dir / "big-endian.den", pp5::test::den_bytes(dims, ramp<std::uint8_t>(24, 10), std::endian::big));
    write_gzipped(dir / "gzipped.den.gz", pp5::test::den_bytes(dims, ramp<std::uint8_t>(24, 10)));
}

void inv3_seeds(const fs::path& dir) {
    const std::string shape = "<integer>2</integer><integer>3</integer><integer>4</integer>";  // z, y, x
    for (const auto& [dtype, samples] : {std::pair{std::string("int16"), ramp<std::int16_t>(24, 90)},
                                         std::pair{std::string("float32"), ramp<float>(24, 1.5f)}}) {
        pp5::test::PlistSpec spec;
        spec.dtype = dtype;
        spec.shape = shape;
        write_gzipped(dir / (dtype + ".inv3"),
                      pp5::test::tar({{"main.plist", text(pp5::test::plist(spec))}, {"matrix.dat", samples}}));
    }
}

// The raw harness reads its layout from the first 16 bytes: three int16 dimensions, a type index, a
// byte-order flag, a uint16 header size and three spacing exponents (64 is 1).
Bytes raw_input(std::int16_t x, std::int16_t y, std::int16_t z, std::uint8_t type, bool big_endian,
                std::uint16_t header, const Bytes& file) {
    Bytes out;
    out.reserve(16 + file.size());
    for (const auto d : {x, y, z}) pp5::test::append(out, d);
    out.push_back(std::byte{type});
    out.push_back(std::byte{static_cast<unsigned char>(big_endian)});
    pp5::test::append(out, header);
    for (int axis = 0; axis < 3; ++axis) out.push_back(std::byte{64});
    out.resize(16);
    out.insert(out.end(), file.begin(), file.end());
    return out;
}

void raw_seeds(const fs::path& dir) {
    write_plain(dir / "uint8.bin", raw_input(4, 3, 2, 0, false, 0, ramp<std::uint8_t>(24, 10)));
    Bytes with_header(8, std::byte{0x1f});
    const Bytes samples = ramp<std::int16_t>(24, 100);
    with_header.insert(with_header.end(), samples.begin(), samples.end());
    write_plain(dir / "int16-header.bin", raw_input(4, 3, 2, 3, false, 8, with_header));
    write_plain(dir / "float32-big-endian.bin", raw_input(2, 2, 2, 6, true, 0, Bytes(32, std::byte{0x3f})));
}

void obj_seeds(const fs::path& dir) {
    write_plain(dir / "tetrahedron.obj",
                text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n"));
    write_plain(dir / "quad-relative.obj",
                text("o quad\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nf -4//1 -3//1 -2//1 -1//1\n"));
    write_plain(dir / "textured.obj",
                text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\ng part\nf 1/1 2/2 3/3\n"));
}

// A whole sweep as one shard: two scenarios over two GP counts, one point failed.
void shard_seeds(const fs::path& dir) {
    write_plain(dir / "shard-0-of-1.json",
                text(R"({"sweep": {"name": "seed", "description": "", "scenarios": ["a", "b"],
  "machine": "pxpl5", "set": [], "frames": 1, "axes": [{"key": "gp.count", "values": ["4", "8"]}], "points": [],
  "total_points": 4, "plot_x": "", "plot_metric": "frame_ms", "kernels": {"a": "levoy", "b": "yuan"}},
 "columns": [{"name": "frame_ms", "unit": "ms", "description": "frame time"}, {"name": "hits", "unit": "count", "description": "hits"}],
 "results": [
  {"index": 0, "scenario": "a", "varied": {"gp.count": "4"}, "parameters": {"gp.count": 4},
   "frames": [{"frame": 0, "label": "f", "metrics": {"frame_ms": 12.5, "hits": null}}]},
  {"index": 1, "scenario": "a", "varied": {"gp.count": "8"}, "parameters": {"gp.count": 8},
   "frames": [{"frame": 0, "label": "f", "metrics": {"frame_ms": 7.0, "hits": 3}}]},
  {"index": 2, "scenario": "b", "varied": {"gp.count": "4"}, "parameters": {"gp.count": 4}, "error": "too small", "frames": []},
  {"index": 3, "scenario": "b", "varied": {"gp.count": "8"}, "parameters": {"gp.count": 8},
   "frames": [{"frame": 0, "label": "f", "metrics": {"frame_ms": 3.25, "hits": 1}}]}],
 "shard": {"index": 0, "count": 1}}
)"));
}

// A run's statistics in the shape `pp5sim render` writes, with a statistic, a histogram and frames.
void compare_seeds(const fs::path& dir) {
    write_plain(dir / "stats.json",
                text(R"({"summary": {"scenario": "s", "kernel": "levoy", "machine": "pxpl5", "frames": 2,
  "simulated_seconds": [0.016, 0.012], "host_seconds": 0.2},
 "components": {"gp[0]": {"busy_time": {"value": 1.5e9, "unit": "ps", "description": "busy"},
   "latency": {"value": {"bounds": [0, 10, 100], "counts": [3, 4], "sum": 250}, "unit": "ns", "description": "latency"}}},
 "frames": [{"simulated_seconds": 0.016, "label": "a"}, {"simulated_seconds": 0.012, "label": "b"}],
 "simulation": {"events_run": 10}, "dataset": {}, "placement": {}}
)"));
}

// Requests as a browser sends them, and a few it would not.
void http_seeds(const fs::path& dir) {
    write_plain(dir / "get-state", text("GET /api/state HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-page",
                text("GET / HTTP/1.1\r\nHost: localhost\r\nAccept: text/html\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-pass", text("GET /api/pass/0.png HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    // A change as the page posts it.
    const auto post_change = [](const std::string& body) {
        return text(
            "POST /api/change HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\nContent-Length: " +
            std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body);
    };
    write_plain(dir / "post-change",
                post_change(R"({"camera": {"azimuth": 30}, "light": {"direction": [0.2, 1.0, 0.3]}})"));
    write_plain(dir / "post-chunked",
                text("POST /api/change HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
                     "Transfer-Encoding: chunked\r\nConnection: close\r\n\r\n2\r\n{}\r\n0\r\n\r\n"));
    write_plain(dir / "delete-state",
                text("DELETE /api/state HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-timeline",
                text("GET /api/timeline.json HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-fidelity",
                text("GET /api/fidelity.json HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-tiles", text("GET /api/tiles.png HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "get-compared",
                text("GET /api/compare/levoy.png HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n"));
    write_plain(dir / "post-lights",
                post_change(R"({"light": {"stationary": [{"direction": [-1.0, 0.2, 0.3], "intensity": 0.6}]}})"));
}

// Every shipped file of a kind, as it is: the richest valid inputs there are.
void copy_shipped(const fs::path& from, const fs::path& dir) {
    for (const auto& entry : fs::directory_iterator(from))
        if (entry.path().extension() == ".toml")
            fs::copy_file(entry.path(), dir / entry.path().filename(), fs::copy_options::overwrite_existing);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: make_fuzz_seeds OUT_DIR SOURCE_DIR\n";
        return 2;
    }
    const fs::path out(argv[1]);
    const fs::path source(argv[2]);
    try {
        const auto make = [&](const std::string& harness, auto&& write) {
            const fs::path dir = out / harness;
            fs::remove_all(dir);
            fs::create_directories(dir);
            write(dir);
        };
        make("nifti", nifti_seeds);
        make("den", den_seeds);
        make("inv3", inv3_seeds);
        make("raw", raw_seeds);
        make("obj", obj_seeds);
        make("scenario", [&](const fs::path& dir) { copy_shipped(source / "traces/scenarios", dir); });
        make("machine", [&](const fs::path& dir) { copy_shipped(source / "sim/machines", dir); });
        make("targets", [&](const fs::path& dir) { copy_shipped(source / "traces/calibration", dir); });
        make("shard", shard_seeds);
        make("compare", compare_seeds);
        make("http", http_seeds);
    } catch (const std::exception& e) {
        std::cerr << "make_fuzz_seeds: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
