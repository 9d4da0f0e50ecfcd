// The kernel conformance suite: the same promises checked for every kernel the registry lists, on the
// scenario its folder brings (kernels/<folder>/tests/conformance.toml). A new kernel is held to them
// as soon as its registry line exists: its folder must bring the scenario, and each test below runs
// for it. Parameters that act only on one of a kernel's paths, or on data the small scenario lacks,
// are also tried under the settings and scenarios its folder's conformance_settings.toml names.
//
// The promises (the house's standards, kernel by kernel): each renders its scenario's frames at their
// size, with work for the machine when it runs on one; the same inputs give the same pictures and
// statistics at 1 and 2 threads; every parameter and cost it declares changes something a frame
// computes or takes; a value outside a parameter's range and a feature the kernel lacks are refused
// naming the file and the field; a frame that changes nothing recomputes nothing; its pictures stay
// near the host's oracle; and a golden scenario pins its statistics.

#include "calibration/timing_model.h"
#include "frontends/render_session.h"
#include "kernels/registry/registry.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"
#include "sim/core/toml_file.h"
#include "sim/core/toml_table.h"
#include "tests/support/input_errors.h"
#include "tests/support/param_values.h"
#include "tests/support/run_files.h"
#include "tests/support/source_dir.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

// Every kernel folder's conformance scenario, by the kernel it names.
const std::map<std::string, fs::path>& conformance_scenarios() {
    static const std::map<std::string, fs::path> found = [] {
        std::map<std::string, fs::path> by_kernel;
        for (const fs::directory_entry& folder : fs::directory_iterator(test::source_dir() / "kernels")) {
            const fs::path file = folder.path() / "tests" / "conformance.toml";
            if (fs::exists(file)) by_kernel[load_scenario(file).kernel] = file;
        }
        return by_kernel;
    }();
    return found;
}

// Where else a kernel's parameters are tried (conformance_settings.toml beside its scenario): each
// variant a scenario of the same folder (conformance.toml unless it names another) under machine and
// kernel settings (`--set` assignments).
struct ConformanceVariant {
    fs::path scenario;
    std::vector<std::string> settings;
};

std::vector<ConformanceVariant> conformance_variants(const fs::path& scenario_file) {
    std::vector<ConformanceVariant> variants;
    const fs::path file = scenario_file.parent_path() / "conformance_settings.toml";
    if (!fs::exists(file)) return variants;
    const toml::table root = read_toml_file(file.string());
    TomlTable top(&root, "", file.string());
    top.table_array("variants", [&](TomlTable& variant) {
        variant.required_text("why");
        const std::optional<std::string> other = variant.text("scenario");
        variants.push_back({other ? scenario_file.parent_path() / *other : scenario_file,
                            variant.text_list("set").value_or(std::vector<std::string>{})});
    });
    top.finish();
    return variants;
}

std::vector<std::string> registered_kernel_names() {
    std::vector<std::string> names;
    for (const Kernel* k : kernels()) names.push_back(k->name());
    return names;
}

// FNV-1a over a picture's size and its pixels' float bits.
std::uint64_t picture_digest(const Image& image) {
    std::uint64_t h = 1469598103934665603ull;
    const auto mix = [&h](std::uint64_t word) {
        for (int b = 0; b < 8; ++b, word >>= 8) {
            h ^= word & 0xff;
            h *= 1099511628211ull;
        }
    };
    mix(static_cast<std::uint64_t>(image.width));
    mix(static_cast<std::uint64_t>(image.height));
    for (const glm::vec4& p : image.pixels)
        for (int c = 0; c < 4; ++c) {
            std::uint32_t bits = 0;
            std::memcpy(&bits, &p[c], sizeof bits);
            mix(bits);
        }
    return h;
}

// One run of a scenario: every frame's pictures and record (host timings left out), the run's
// statistics, and the frames' times on a lone processor, as comparable text.
struct RunOutcome {
    std::vector<std::string> frames;  // per frame: its record and its pictures' digests
    std::vector<SessionFrame> session_frames;
    std::string run;  // the run's statistics and the lone processor's times

    std::string digest() const {
        std::string all = run;
        for (const std::string& f : frames) all += f;
        return all;
    }
};

struct RunOptions {
    std::vector<std::string> overrides;
    bool compare_with_reference = false;
    std::size_t frames = 0;  // 0: all of the scenario's
};

RunOutcome run_scenario(const Scenario& scenario, const RunOptions& options = {}) {
    const MachineConfig config = load_run_config("pxpl5", options.overrides);
    RenderSession session(scenario, config, nullptr, "png", options.compare_with_reference);
    RunOutcome out;
    nlohmann::json records = nlohmann::json::array();
    const std::size_t count = options.frames == 0 ? scenario.frames.size() : options.frames;
    for (std::size_t f = 0; f < count; ++f) {
        SessionFrame frame = session.render(scenario.frames[f]);
        std::string text = test::without_host_fields(frame.record).dump();
        for (const FrameImage& image : frame.images)
            text += fmt::format(" {}:{:x}", image.name, picture_digest(image.image));
        out.frames.push_back(std::move(text));
        records.push_back(frame.record);
        out.session_frames.push_back(std::move(frame));
    }
    out.run = test::without_host_fields(session.stats(records, 0.0)).dump();
    if (session.kernel().runs_on_machine()) {
        std::vector<const FrameWork*> work;
        for (const SessionFrame& frame : out.session_frames) work.push_back(&frame.recorded->work);
        for (const FrameTiming& t : time_recorded_work(load_run_config("sun4-280", options.overrides), work))
            out.run += fmt::format(" lone processor {}", t.duration_ps());
    }
    return out;
}

class KernelConformance : public ::testing::TestWithParam<std::string> {
protected:
    const Kernel& kernel() const { return *find_kernel(GetParam()); }
    // The kernel's own scenario (a test fails, not the suite, when its folder brings none).
    const Scenario& scenario() {
        if (!scenario_) {
            const auto found = conformance_scenarios().find(GetParam());
            if (found == conformance_scenarios().end())
                throw std::runtime_error("the " + GetParam() + " kernel's folder brings no tests/conformance.toml");
            scenario_ = load_scenario(found->second);
        }
        return *scenario_;
    }

    // check_scenario refuses `asking`, naming the scenario's file and `field`.
    void expect_refusal_naming(const Scenario& asking, const std::string& field) {
        const InputError e = test::input_error_from([&] { check_scenario(kernel(), asking); });
        EXPECT_NE(std::string(e.what()).find(scenario().file.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }

private:
    std::optional<Scenario> scenario_;
};

TEST_P(KernelConformance, BringsAScenarioAndAGoldenOne) {
    ASSERT_TRUE(conformance_scenarios().count(GetParam()))
        << "kernels/<folder>/tests/conformance.toml naming kernel = \"" << GetParam() << "\"";
    if (!kernel().runs_on_machine()) GTEST_SKIP() << "renders on the host only: no machine statistics to pin";
    // The golden test renders every shipped scenario (tests/golden).
    bool golden = false;
    for (const fs::directory_entry& file : fs::directory_iterator(test::source_dir() / "traces" / "scenarios"))
        if (file.path().extension() == ".toml" && load_scenario(file.path()).kernel == GetParam()) golden = true;
    EXPECT_TRUE(golden) << "no scenario in traces/scenarios renders with kernel = \"" << GetParam() << "\"";
}

TEST_P(KernelConformance, RendersEachFrameAtItsSizeWithWorkForTheMachine) {
    const RunOutcome run = run_scenario(scenario());
    ASSERT_EQ(run.session_frames.size(), scenario().frames.size());
    for (const SessionFrame& frame : run.session_frames) {
        const Image* picture = frame.find(FrameImage::Kind::Frame);
        ASSERT_NE(picture, nullptr);
        EXPECT_EQ(picture->width, scenario().image.width);
        EXPECT_EQ(picture->height, scenario().image.height);
        bool lit = false;
        for (const glm::vec4& p : picture->pixels) lit = lit || p.r > 0.0f || p.g > 0.0f || p.b > 0.0f;
        EXPECT_TRUE(lit) << "frame " << frame.index << " is black";
        if (kernel().runs_on_machine()) {
            EXPECT_FALSE(frame.recorded->work.phases.empty()) << "frame " << frame.index;
            EXPECT_GT(frame.timing.duration_ps(), 0u) << "frame " << frame.index;
        } else {
            EXPECT_TRUE(frame.recorded->work.phases.empty()) << "frame " << frame.index;
        }
    }
}

TEST_P(KernelConformance, SameResultsAtOneAndTwoThreads) {
    std::string one, two;
    {
        const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
        one = run_scenario(scenario()).digest();
    }
    {
        const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
        two = run_scenario(scenario()).digest();
    }
    EXPECT_EQ(one, two);
}

TEST_P(KernelConformance, PicturesStayNearTheOracle) {
    if (!kernel().runs_on_machine()) GTEST_SKIP() << "it is the oracle";
    // Every kernel approximates the host's floating-point renderer; 30 dB is a picture a viewer
    // takes for the same one, with the approximations the kernels' papers make.
    constexpr double kFloorDb = 30.0;
    RunOptions options;
    options.compare_with_reference = true;
    const RunOutcome run = run_scenario(scenario(), options);
    for (const SessionFrame& frame : run.session_frames) {
        ASSERT_TRUE(frame.record.contains("fidelity")) << frame.record.dump();
        const nlohmann::json& psnr = frame.record["fidelity"]["psnr_db"];
        if (psnr.is_number()) {  // null: the pictures are identical
            EXPECT_GE(psnr.get<double>(), kFloorDb) << "frame " << frame.index;
        }
    }
}

TEST_P(KernelConformance, AFrameThatChangesNothingRecomputesNothing) {
    // The first frame twice: the second must give the same picture, and the machine no work the first
    // did not need (what the first left in the PPs, the pyramid or the caches stays valid).
    Scenario twice = scenario();
    twice.frames.resize(1);
    FrameSpec again = twice.frames.front();
    again.label = "again";
    again.camera_changed = again.lighting_changed = again.classification_changed = false;
    twice.frames.push_back(again);
    const RunOutcome run = run_scenario(twice);
    const Image* first = run.session_frames[0].find(FrameImage::Kind::Frame);
    const Image* second = run.session_frames[1].find(FrameImage::Kind::Frame);
    ASSERT_TRUE(first != nullptr && second != nullptr);
    EXPECT_EQ(picture_digest(*first), picture_digest(*second));
    const FrameWork& before = run.session_frames[0].recorded->work;
    const FrameWork& after = run.session_frames[1].recorded->work;
    EXPECT_LE(after.phases.size(), before.phases.size());
    for (const Phase& phase : after.phases) {
        if (const auto* pp = std::get_if<PpPhase>(&phase.work)) {
            EXPECT_TRUE(pp->passes.empty()) << "phase " << phase.name << " runs PP programs again";
        }
    }
    EXPECT_LE(run.session_frames[1].timing.duration_ps(), run.session_frames[0].timing.duration_ps());
}

TEST_P(KernelConformance, EveryParameterAndCostChangesSomething) {
    // Where a parameter is tried: the scenario as it is, then each variant the kernel's folder names,
    // each with what it gives untouched. Untouched runs are made up front; a parameter stops at the
    // first trial it changes.
    struct Trial {
        Scenario scenario;
        std::vector<std::string> overrides;
        std::optional<std::string> untouched;
    };
    std::vector<Trial> trials{{scenario(), {}, {}}};
    for (const ConformanceVariant& variant : conformance_variants(conformance_scenarios().at(GetParam())))
        trials.push_back({load_scenario(variant.scenario), variant.settings, {}});
    for (Trial& trial : trials) {
        // A variant the kernel refuses would try nothing: say so.
        ASSERT_NO_THROW(trial.untouched = run_scenario(trial.scenario, {trial.overrides}).digest())
            << trial.scenario.file << " with " << fmt::format("{}", fmt::join(trial.overrides, ", "));
    }

    std::size_t checked = 0;
    for (const ParamGroup* group : kernel().param_groups()) {
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            bool tried = false, changed = false;
            for (Trial& trial : trials) {
                for (const std::string& value : test::other_values(spec)) {
                    std::vector<std::string> overrides = trial.overrides;
                    overrides.push_back(key + "=" + value);
                    try {
                        changed = run_scenario(trial.scenario, {overrides}).digest() != *trial.untouched;
                        tried = true;
                    } catch (const InputError&) {
                        continue;  // the run cannot take that value (a machine that cannot hold it): the next
                    }
                    if (changed) break;
                }
                if (changed) break;
            }
            EXPECT_TRUE(tried) << key << ": no other value could be tried";
            EXPECT_TRUE(changed) << key << " changes nothing in the frames, their statistics or their times";
            ++checked;
        }
    }
    if (kernel().runs_on_machine()) {
        EXPECT_GT(checked, 0u);
    }
}

TEST_P(KernelConformance, RefusesValuesOutOfRangeNamingTheKey) {
    for (const ParamGroup* group : kernel().param_groups()) {
        for (const ParamSpec& spec : group->specs()) {
            const std::string key = group->prefix() + "." + spec.name;
            std::string bad;
            if (spec.max) bad = fmt::format("{}", *spec.max + 1);
            else if (spec.min) bad = fmt::format("{}", *spec.min - 1);
            else if (spec.type == pp5::ParamType::Text && !spec.choices.empty()) bad = "no-such-choice";
            else continue;
            const InputError e = test::input_error_from([&] { load_run_config("pxpl5", {key + "=" + bad}); });
            EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << key << " = " << bad << ": " << e.what();
        }
    }
}

TEST_P(KernelConformance, RefusesWhatItLacksNamingTheFileAndField) {
    const KernelFeatures has = kernel().features();
    Scenario asking = scenario();
    if (!has.polygons) {
        PolygonSpec polygon;
        polygon.vertices = {{4.0f, 16.0f, 6.0f}, {28.0f, 16.0f, 6.0f}, {28.0f, 16.0f, 26.0f}};
        polygon.colors = {glm::vec3(0.9f, 0.2f, 0.2f)};
        polygon.opacities = {0.9f};
        asking.polygons.push_back(polygon);
        expect_refusal_naming(asking, "polygons");
        asking.polygons.clear();
    }
    if (!has.regions) {
        RegionOfInterest region;
        region.center = glm::vec3(16.0f);
        region.half_size = glm::vec3(4.0f);
        asking.frames.front().region = region;
        asking.frames.front().region_changed = true;
        expect_refusal_naming(asking, "region");
    }
    if (has.polygons && has.regions) GTEST_SKIP() << "it has every feature a scenario can ask for";
}

std::string kernel_name(const ::testing::TestParamInfo<std::string>& kernel) { return kernel.param; }

INSTANTIATE_TEST_SUITE_P(EveryKernel, KernelConformance, ::testing::ValuesIn(registered_kernel_names()), kernel_name);

}  // namespace
}  // namespace pp5
