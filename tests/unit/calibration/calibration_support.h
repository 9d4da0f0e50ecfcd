#pragma once
// A small machine and scenario for calibration tests: a 48^3 sphere on four 32x32 renderers and four
// GPs, 64x64 images, three frames (first, observer moved, light moved).

#include "calibration/targets.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace pp5::test {

struct CalibrationFiles {
    std::filesystem::path dir;
    std::filesystem::path machine;
    std::filesystem::path scenario;
};

inline CalibrationFiles write_calibration_files(const std::string& name) {
    namespace fs = std::filesystem;
    CalibrationFiles files;
    // The process id keeps tests that run side by side (ctest -j) out of each other's files.
    files.dir = fs::temp_directory_path() / ("pp5_calibration_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(files.dir);
    fs::create_directories(files.dir);
    files.machine = files.dir / "tiny.toml";
    std::ofstream(files.machine) << R"([machine]
name = "tiny"

[gp]
count = 4

[renderer]
count = 4
pp_columns = 32
pp_rows = 32
)";
    files.scenario = files.dir / "sphere-frames.toml";
    std::ofstream(files.scenario) << R"([scenario]
name = "sphere-frames"

[dataset]
phantom = "sphere"
size = 48

[classification]
kind = "piecewise-linear"
points = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, opacity = 0.8 }]

[shading]
light_direction = [0.3, 1.0, 0.4]

[image]
width = 64
height = 64

[[frames]]
label = "first"

[[frames]]
label = "observer moved"
camera = { azimuth = 20.0 }

[[frames]]
label = "light moved"
shading = { light_direction = [-0.5, 1.0, 0.2] }
)";
    return files;
}

// A measured row of the calibration scenario on the calibration machine, in seconds, reported as 1 until
// a test sets it.
inline Target make_target(const CalibrationFiles& files, const std::string& id, int frame, const std::string& metric) {
    Target t;
    t.id = id;
    t.source = "synthetic";
    t.scenario = files.scenario.string();
    t.frame = frame;
    t.machine = files.machine.string();
    t.metric = metric;
    t.unit = std::string("s");  // every metric these tests use is in seconds (a string: GCC 12 misreads the literal)
    t.reported = 1.0;
    t.exactness = Exactness::Measured;
    return t;
}

}  // namespace pp5::test
