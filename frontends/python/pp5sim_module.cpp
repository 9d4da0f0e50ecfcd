// The `pp5sim` Python module (pybind11): the simulator for notebooks and lectures. The same paths as the
// CLI: scenarios and machines are read and checked by the same loaders, a render is a RenderSession, a
// recording is calibration's RecordedScenario (re-timed on other machines without rendering again), and
// a View is the browser tool's. Pictures arrive as NumPy arrays, statistics as nested dicts (each
// statistic with its unit and description, as in stats.json), and bad input as pp5sim.InputError with
// the CLI's file, field and reason. See docs/python.md.

#include "calibration/timing_model.h"
#include "frontends/compare_kernels.h"
#include "frontends/render_session.h"
#include "frontends/serve/interactive_view.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

namespace py = pybind11;

namespace pp5 {
namespace {

py::object to_python(const nlohmann::json& value) { return py::module_::import("json").attr("loads")(value.dump()); }

nlohmann::json from_python(const py::handle& value, const char* what) {
    try {
        return nlohmann::json::parse(py::module_::import("json").attr("dumps")(value).cast<std::string>());
    } catch (const py::error_already_set&) {
        throw InputError("python", what, "must be made of dicts, lists, strings, numbers, booleans and None");
    }
}

py::array_t<float> to_array(const Image& image) {
    py::array_t<float> array({image.height, image.width, 4});
    std::memcpy(array.mutable_data(), image.pixels.data(), image.pixels.size() * sizeof(glm::vec4));
    return array;
}

// A machine parameter's value as the machine files and --set write it.
std::string override_text(const std::string& key, const py::handle& value) {
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value))
        return py::repr(value).cast<std::string>();
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    throw InputError("python", key, "a parameter's value is a number, a boolean or a string");
}

std::vector<std::string> override_texts(const py::dict& set) {
    std::vector<std::string> out;
    for (const auto& [key, value] : set) {
        const std::string k = py::str(key).cast<std::string>();
        out.push_back(k + "=" + override_text(k, value));
    }
    return out;
}

// A configured machine: a preset or machine file, with parameters set.
struct PyMachine {
    std::string base;
    std::vector<std::string> overrides;
    MachineConfig config;

    PyMachine(std::string machine, std::vector<std::string> set)
        : base(std::move(machine)), overrides(std::move(set)), config(load_run_config(base, overrides)) {}
    PyMachine(std::string machine, const py::dict& set) : PyMachine(std::move(machine), override_texts(set)) {}
    // The same machine with more parameters set.
    PyMachine with_set(const py::dict& set) const {
        std::vector<std::string> all = overrides;
        for (std::string& o : override_texts(set)) all.push_back(std::move(o));
        return PyMachine(base, std::move(all));
    }
};

PyMachine default_machine() { return PyMachine("pxpl5", std::vector<std::string>{}); }

struct PyFrame {
    std::string label;
    double simulated_seconds = 0.0;
    py::dict utilisation;
    py::array_t<float> image;
    py::list passes;
    py::object record;
};

struct PyRun {
    std::vector<PyFrame> frames;
    py::object stats;
    py::object config;
};

// A Scenario, or the name or path of one as the CLI takes it ("sphere", "traces/scenarios/mr-head.toml").
Scenario scenario_of(const py::object& given) {
    if (py::isinstance<py::str>(given)) return load_scenario(resolve_scenario_file(given.cast<std::string>()));
    return given.cast<Scenario>();
}

PyRun render(const py::object& scenario_given, const std::optional<PyMachine>& machine_given,
             std::optional<std::size_t> frame_count) {
    const Scenario scenario = scenario_of(scenario_given);
    const PyMachine machine = machine_given.value_or(default_machine());
    const std::size_t count = std::min(frame_count.value_or(scenario.frames.size()), scenario.frames.size());
    std::vector<SessionFrame> rendered;
    nlohmann::json stats;
    {
        const py::gil_scoped_release unlocked;  // the render takes seconds and runs its own threads
        const auto started = std::chrono::steady_clock::now();
        RenderSession session(scenario, machine.config);
        nlohmann::json records = nlohmann::json::array();
        for (std::size_t i = 0; i < count; ++i) {
            rendered.push_back(session.render(scenario.frames[i]));
            records.push_back(rendered.back().record);
        }
        stats =
            session.stats(records, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    }
    PyRun run;
    for (std::size_t i = 0; i < rendered.size(); ++i) {
        const SessionFrame& f = rendered[i];
        PyFrame frame;
        frame.label = scenario.frames[i].label;
        frame.simulated_seconds = ticks_to_seconds(f.timing.duration_ps());
        frame.utilisation["gps"] = f.timing.activity.gps;
        frame.utilisation["renderers"] = f.timing.activity.renderers;
        frame.utilisation["ring"] = f.timing.activity.ring;
        frame.image = to_array(*f.find(FrameImage::Kind::Frame));
        for (const FrameImage& image : f.images)
            if (image.kind == FrameImage::Kind::Pass) frame.passes.append(to_array(image.image));
        frame.record = to_python(f.record);
        run.frames.push_back(std::move(frame));
    }
    run.stats = to_python(stats);
    run.config = to_python(machine.config.to_json());
    return run;
}

// One recorded frame timed on a machine: what re-timing gives, as attributes.
struct PyTiming {
    std::string label;
    std::string machine;  // the machine's name and the parameters set on it
    double simulated_seconds = 0.0;
    py::dict phases;   // name -> simulated seconds
    py::dict metrics;  // the kernel's metrics this frame has
    std::optional<double> frames_per_second() const {
        return simulated_seconds > 0 ? std::optional<double>(1.0 / simulated_seconds) : std::nullopt;
    }
};

// A recording's frames timed on one machine: a sequence of Timing, and a table of them.
struct PyTimings {
    std::vector<PyTiming> frames;

    // One row a frame: label, machine, simulated seconds and rate, then each phase's seconds
    // ("phase.<name>") and each metric, as pandas.DataFrame when pandas is installed.
    py::object to_dataframe() const {
        py::module_ pandas;
        try {
            pandas = py::module_::import("pandas");
        } catch (const py::error_already_set&) {
            throw py::import_error(
                "to_dataframe needs pandas (Debian: apt install python3-pandas); the frames are also "
                "a list of pp5sim.Timing with attributes");
        }
        py::list rows;
        for (const PyTiming& t : frames) {
            py::dict row;
            row["label"] = t.label;
            row["machine"] = t.machine;
            row["simulated_seconds"] = t.simulated_seconds;
            row["frames_per_second"] = t.frames_per_second();
            for (const auto& [name, seconds] : t.phases)
                row[py::str("phase." + py::str(name).cast<std::string>())] = seconds;
            for (const auto& [name, value] : t.metrics) row[name] = value;
            rows.append(row);
        }
        return pandas.attr("DataFrame")(rows);
    }
};

// The machine as a row names it: its name and what was set on it.
std::string machine_label(const PyMachine& machine) {
    std::string label = machine.config.machine_name();
    for (const std::string& o : machine.overrides) label += " " + o;
    return label;
}

// A scenario's frames recorded once, re-timed on any machine that differs only in timing.
struct PyRecording {
    std::shared_ptr<RecordedScenario> recorded;
    MachineConfig functional;

    PyTimings time_on(const PyMachine& machine) const {
        std::vector<FrameTiming> timings;
        {
            const py::gil_scoped_release unlocked;
            timings = recorded->time_on(machine.config);
        }
        PyTimings out;
        for (std::size_t i = 0; i < timings.size(); ++i) {
            PyTiming frame;
            frame.label = recorded->frames()[i].label;
            frame.machine = machine_label(machine);
            frame.simulated_seconds = ticks_to_seconds(timings[i].duration_ps());
            for (const PhaseTiming& p : timings[i].phases)
                frame.phases[py::str(p.name)] = ticks_to_seconds(p.duration_ps());
            for (const KernelMetric& m : recorded->kernel().metrics()) {
                try {
                    frame.metrics[py::str(m.name)] = recorded->metric(m.name, i, timings[i]);
                } catch (const std::domain_error&) {
                    // This frame cannot give it.
                }
            }
            out.frames.push_back(std::move(frame));
        }
        return out;
    }
};

PyRecording record(const py::object& scenario_given, const std::optional<PyMachine>& machine_given) {
    const Scenario scenario = scenario_of(scenario_given);
    const PyMachine machine = machine_given.value_or(default_machine());
    const py::gil_scoped_release unlocked;
    return {std::make_shared<RecordedScenario>(scenario, machine.config, static_cast<int>(scenario.frames.size())),
            machine.config};
}

// Every kernel on one scenario and machine (frontends/compare_kernels.h): the report as a dict, with
// each rendered kernel's last picture as an array under "pictures".
py::object compare_kernels_of(const py::object& scenario_given, const std::optional<PyMachine>& machine_given,
                              bool reference) {
    const Scenario scenario = scenario_of(scenario_given);
    const PyMachine machine = machine_given.value_or(default_machine());
    KernelComparison comparison;
    {
        const py::gil_scoped_release unlocked;
        comparison = compare_kernels(scenario, machine.config, {reference});
    }
    py::dict report = to_python(to_json(comparison)).cast<py::dict>();
    py::dict pictures;
    for (const KernelComparisonRow& row : comparison.rows)
        if (row.rendered()) pictures[py::str(row.kernel)] = to_array(row.picture);
    report["pictures"] = pictures;
    return report;
}

// InputError as a ValueError carrying the CLI's file, field and reason.
void bind_input_error(py::module_& m) {
    static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            py::object error = py::handle(input_error.ptr())(e.what());
            error.attr("file") = e.file();
            error.attr("field") = e.field();
            error.attr("reason") = e.reason();
            PyErr_SetObject(input_error.ptr(), error.ptr());
        }
    });
}

// The shipped scenarios, the kernels, and Scenario with its loaders.
void bind_scenarios(py::module_& m) {
    m.def(
        "scenarios",
        [] {
            std::vector<std::string> names;
            for (const auto& file : shipped_scenario_files()) names.push_back(file.stem().string());
            return names;
        },
        "Names of the shipped scenarios (traces/scenarios/)");
    m.def(
        "kernels",
        [] {
            py::list out;
            for (const Kernel* k : pp5::kernels()) {
                py::dict d;
                d["name"] = k->name();
                d["description"] = k->description();
                d["runs_on_machine"] = k->runs_on_machine();
                out.append(d);
            }
            return out;
        },
        "The registered kernels: name, description, whether they run on the simulated machine");

    py::class_<Scenario>(m, "Scenario", "What to render: a dataset, classification, shading, camera, image and frames")
        .def_readonly("name", &Scenario::name)
        .def_readonly("description", &Scenario::description)
        .def_readwrite("kernel", &Scenario::kernel, "The kernel that renders it (a name from pp5sim.kernels())")
        .def_property(
            "image_size",
            [](const Scenario& s) {
                return std::pair{s.image.width, s.image.height};
            },
            [](Scenario& s, std::pair<int, int> size) {
                if (size.first < 1 || size.second < 1 || size.first > 16384 || size.second > 16384)
                    throw InputError("python", "image_size", "width and height lie in [1, 16384]");
                s.image.width = size.first;
                s.image.height = size.second;
            },
            "(width, height) of the pictures")
        .def_property_readonly("frame_labels",
                               [](const Scenario& s) {
                                   std::vector<std::string> labels;
                                   for (const FrameSpec& f : s.frames) labels.push_back(f.label);
                                   return labels;
                               })
        .def("__repr__", [](const Scenario& s) {
            return fmt::format("<pp5sim.Scenario {} ({} kernel, {} frames, {}x{})>", s.name, s.kernel, s.frames.size(),
                               s.image.width, s.image.height);
        });
    m.def(
        "load_scenario", [](const std::string& name) { return load_scenario(resolve_scenario_file(name)); },
        py::arg("name_or_path"), "A scenario file, or the name of a shipped one");
    m.def(
        "scenario_from_toml",
        [](const std::string& text, const std::string& directory) {
            return load_scenario_text(text, std::filesystem::absolute(directory) / "<python>.toml");
        },
        py::arg("text"), py::arg("directory") = ".",
        "A scenario written in TOML (traces/README.md); relative paths start from directory");
}

// Machine: a preset or machine file with parameters set.
void bind_machine(py::module_& m) {
    py::class_<PyMachine>(m, "Machine", "A configured machine: a preset or machine file, with parameters set")
        .def(py::init<std::string, py::dict>(), py::arg("machine") = "pxpl5", py::arg("set") = py::dict())
        .def("with_set", &PyMachine::with_set, py::arg("set"), "The same machine with these parameters set as well")
        .def_property_readonly("name", [](const PyMachine& p) { return p.config.machine_name(); })
        .def_property_readonly(
            "parameters",
            [](const PyMachine& p) {
                const nlohmann::json all = p.config.to_json();
                return to_python(all["parameters"]);
            },
            "Every parameter: value, unit, description, where it was set")
        .def("__getitem__",
             [](const PyMachine& p, const std::string& key) {
                 const nlohmann::json all = p.config.to_json();
                 if (!all["parameters"].contains(key))
                     throw InputError("python", key, "no such parameter (see pp5sim params)");
                 return to_python(all["parameters"][key]["value"]);
             })
        .def("__repr__", [](const PyMachine& p) {
            return fmt::format("<pp5sim.Machine {} with {} set>", p.config.machine_name(), p.overrides.size());
        });
}

// render(): a scenario's frames on a machine, as Run and its Frames.
void bind_rendering(py::module_& m) {
    py::class_<PyFrame>(m, "Frame", "One rendered frame")
        .def_readonly("label", &PyFrame::label)
        .def_readonly("simulated_seconds", &PyFrame::simulated_seconds)
        .def_readonly("utilisation", &PyFrame::utilisation,
                      "Busy time over count x frame time, for gps, renderers and ring")
        .def_readonly("image", &PyFrame::image, "The picture, height x width x RGBA float32")
        .def_readonly("passes", &PyFrame::passes,
                      "The picture after each stage (refinement pass); the last is the frame")
        .def_readonly("record", &PyFrame::record, "The frame's record in stats.json");
    py::class_<PyRun>(m, "Run", "A scenario rendered on a machine")
        .def_readonly("frames", &PyRun::frames)
        .def_readonly("stats", &PyRun::stats, "What stats.json holds: every component's statistics with units")
        .def_readonly("config", &PyRun::config, "The resolved configuration (config.json)");
    m.def("render", &render, py::arg("scenario"), py::arg("machine") = std::nullopt, py::arg("frames") = std::nullopt,
          "Render the scenario's frames (all, or the first `frames`) on the machine (default pxpl5)");
}

// record() and re-timing on other machines (Recording, Timings, Timing); compare_kernels().
void bind_timing(py::module_& m) {
    py::class_<PyTiming>(m, "Timing", "A recorded frame timed on a machine")
        .def_readonly("label", &PyTiming::label)
        .def_readonly("machine", &PyTiming::machine, "The machine's name and the parameters set on it")
        .def_readonly("simulated_seconds", &PyTiming::simulated_seconds)
        .def_property_readonly("frames_per_second", &PyTiming::frames_per_second,
                               "1 / simulated_seconds (None for an untimed frame)")
        .def_readonly("phases", &PyTiming::phases, "Each phase's simulated seconds, by name")
        .def_readonly("metrics", &PyTiming::metrics, "The kernel's metrics this frame has (Levoy's crude_seconds, ...)")
        // The dict these were before, for code written against it: timing["simulated_seconds"].
        .def("__getitem__",
             [](const py::object& self, const std::string& key) {
                 if (key != "label" && key != "machine" && key != "simulated_seconds" && key != "frames_per_second" &&
                     key != "phases" && key != "metrics")
                     throw py::key_error(key);
                 return self.attr(key.c_str());
             })
        .def("__repr__", [](const PyTiming& t) {
            return fmt::format("<pp5sim.Timing {} on {}: {:.6g} s>", t.label, t.machine, t.simulated_seconds);
        });
    py::class_<PyTimings>(m, "Timings", "A recording's frames timed on one machine: a sequence of Timing")
        .def("__len__", [](const PyTimings& t) { return t.frames.size(); })
        .def("__getitem__",
             [](const PyTimings& t, std::ptrdiff_t i) {
                 const auto n = static_cast<std::ptrdiff_t>(t.frames.size());
                 if (i < 0) i += n;
                 if (i < 0 || i >= n) throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(n));
                 return t.frames[static_cast<std::size_t>(i)];
             })
        .def(
            "__iter__", [](const PyTimings& t) { return py::make_iterator(t.frames.begin(), t.frames.end()); },
            py::keep_alive<0, 1>())
        .def("to_dataframe", &PyTimings::to_dataframe,
             "One row a frame (label, machine, simulated_seconds, frames_per_second, phase.<name>, the kernel's "
             "metrics) as a "
             "pandas.DataFrame; pandas.concat of several machines' tables gives a sweep's");
    py::class_<PyRecording>(m, "Recording",
                            "A scenario's frames recorded once, to time on other machines without rendering again")
        .def("time_on", &PyRecording::time_on, py::arg("machine"),
             "Each frame timed on `machine` (which may differ only in timing): Timings, a sequence of Timing with "
             "simulated_seconds, "
             "frames_per_second, phases and the kernel's metrics, and to_dataframe()");
    m.def("record", &record, py::arg("scenario"), py::arg("machine") = std::nullopt,
          "Record the scenario's work on the machine (default pxpl5), for re-timing");

    m.def("compare_kernels", &compare_kernels_of, py::arg("scenario"), py::arg("machine") = std::nullopt,
          py::arg("reference") = true,
          "Render the scenario with every kernel that runs on the machine (default pxpl5): the report `pp5sim "
          "compare-kernels` "
          "writes, as a dict, with each kernel's last picture under 'pictures'");
}

// View: the browser tool's view, driven from Python.
void bind_view(py::module_& m) {
    py::class_<InteractiveView>(m, "View",
                                "The browser tool's view: change the eye, light, region or kernel a step at a time")
        .def(py::init([](const py::object& given, const std::optional<PyMachine>& machine) {
                 const Scenario s = scenario_of(given);
                 const PyMachine chosen = machine.value_or(default_machine());
                 const py::gil_scoped_release unlocked;
                 return std::make_unique<InteractiveView>(s, chosen.config);
             }),
             py::arg("scenario"), py::arg("machine") = std::nullopt)
        .def(
            "apply",
            [](InteractiveView& v, const py::object& change) {
                const nlohmann::json c = from_python(change, "change");
                const py::gil_scoped_release unlocked;
                v.apply(c);
            },
            py::arg("change"),
            "Apply a change ({'camera': {'azimuth': 40}}, {'light': ...}, {'region': ...}, {'kernel': ...}, "
            "{'machine': {'gp.count': 64}}, which re-times the frame when only timing changes); docs/serve.md")
        .def_property_readonly("state", [](const InteractiveView& v) { return to_python(v.state()); })
        .def_property_readonly(
            "png", [](const InteractiveView& v) { return py::bytes(v.frame_png()); }, "The last frame as PNG bytes")
        .def(
            "timeline",
            [](const InteractiveView& v, int bins) {
                if (bins < 1 || bins > 100000) throw InputError("python", "bins", "a timeline has 1 to 100000 bins");
                return to_python(v.timeline(bins));
            },
            py::arg("bins") = 480,
            "Where the last frame's time went: phases, pass times and a lane of busy time per component "
            "(docs/serve.md)")
        .def_property_readonly(
            "tile_map_png",
            [](const InteractiveView& v) -> py::object {
                const auto png = v.tile_map_png();
                return png ? py::object(py::bytes(*png)) : py::object(py::none());
            },
            "The GP tile map of the last frame as PNG bytes (None when its kernel casts no tiles on GPs)")
        .def(
            "compare_kernels",
            [](InteractiveView& v) {
                nlohmann::json report;
                {
                    const py::gil_scoped_release unlocked;
                    report = v.compare_kernels();
                }
                return to_python(report);
            },
            "Every kernel on the view as it stands, as the page's compare mode: the report as a dict");
}

}  // namespace
}  // namespace pp5

PYBIND11_MODULE(pp5sim, m) {
    using namespace pp5;
    m.doc() = "pp5sim: a cycle-approximate simulator of the Pixel-planes 5 volume rendering workstation";
    m.attr("__version__") = PP5SIM_VERSION;
    bind_input_error(m);
    bind_scenarios(m);
    bind_machine(m);
    bind_rendering(m);
    bind_timing(m);
    bind_view(m);
}
