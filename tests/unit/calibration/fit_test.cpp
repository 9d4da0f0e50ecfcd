// The fit recovers scales it generated its own targets with; target files with unknown scenarios,
// metrics or frames, and fits with too few targets, are clear errors.

#include "calibration/fit.h"
#include "calibration/host_check.h"
#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"
#include "tests/support/run_files.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <random>

namespace pp5 {
namespace {

using test::make_target;

// Eight targets made by the model itself at `truth`, one of them held out: seven fitted rows free all
// three scales (fewer than half).
TargetSet synthetic_targets(const test::CalibrationFiles& files, const CalibrationScales& truth) {
    TargetSet set;
    set.file = files.dir / "synthetic.toml";
    set.name = "synthetic";
    set.targets = {make_target(files, "first-crude", 0, "crude_seconds"),  // the pyramid build: GP cycles
                   make_target(files, "first-refined", 0, "refined_seconds"),
                   make_target(files, "orbit-crude", 1, "crude_seconds"),
                   make_target(files, "orbit-refined", 1, "refined_seconds"),  // rays: mostly GP flops
                   make_target(files, "first-pp", 0, "pp_seconds"),
                   make_target(files, "light-pp", 2, "pp_seconds"),
                   make_target(files, "light-refined", 2, "refined_seconds"),
                   make_target(files, "light-crude", 2, "crude_seconds")};
    set.targets.back().use = TargetUse::Predict;  // one held out, predicted only
    const CalibrationModel generator(set, load_run_config(files.machine.string(), {}));
    std::vector<const Target*> all;
    for (const Target& t : generator.targets().targets) all.push_back(&t);
    const std::vector<double> values = generator.simulate(files.machine.string(), truth, all);
    for (std::size_t i = 0; i < values.size(); ++i) set.targets[i].reported = values[i];
    return set;
}

TEST(Fit, RecoversTheScalesItsTargetsWereMadeWith) {
    const test::CalibrationFiles files = test::write_calibration_files("recover");
    // A [calibration] table of its own, as the presets have (the defaults written out): the fitted
    // file must merge it with the fitted values, not add a second table.
    std::ofstream(files.machine, std::ios::app) << "\n[calibration]\ngp_flops_scale = 1.0\ngp_flops_scale_min = 0.5\n"
                                                   "gp_flops_scale_max = 10.0   # the default range\n";
    const CalibrationScales truth{1.8, 0.6, 1.3};
    const TargetSet set = synthetic_targets(files, truth);
    const MachineConfig functional = load_run_config(files.machine.string(), {});
    const CalibrationModel model(set, functional);
    FitOptions options;
    options.leave_one_out = true;
    const FitReport report = fit_targets(model, options);

    const CalibrationScales fitted = report.scales(files.machine.string());
    EXPECT_NEAR(fitted.gp_flops, truth.gp_flops, 0.02 * truth.gp_flops);
    EXPECT_NEAR(fitted.gp_cycles, truth.gp_cycles, 0.02 * truth.gp_cycles);
    EXPECT_NEAR(fitted.pp_cycles, truth.pp_cycles, 0.02 * truth.pp_cycles);
    for (const FittedParameter& p : report.parameters) {
        EXPECT_TRUE(p.free) << p.key << ": " << p.note;
        EXPECT_TRUE(std::isfinite(p.standard_error)) << p.key;
        EXPECT_FALSE(p.at_bound) << p.key;
    }
    // Every target, fitted or held out, is reproduced; leaving one out still predicts it.
    ASSERT_EQ(report.results.size(), set.targets.size());
    for (const TargetResult& r : report.results) {
        EXPECT_LT(std::abs(r.relative_error), 0.01) << r.target.id;
        if (r.target.fitted()) {
            ASSERT_TRUE(r.leave_one_out_error.has_value()) << r.target.id;
            EXPECT_LT(std::abs(*r.leave_one_out_error), 0.05) << r.target.id;
        }
    }
    EXPECT_EQ(report.summary(RowGroup::Fitted).count, 7);
    EXPECT_EQ(report.summary(RowGroup::Predicted).count, 1);
    EXPECT_EQ(report.summary(RowGroup::Fitted).within_10 + report.summary(RowGroup::Predicted).within_10, 8);
    // Seven rows, three free scales, no workload parameters.
    ASSERT_EQ(report.freedom.size(), 1u);
    EXPECT_EQ(report.freedom[0].degrees_of_freedom(), 4);

    // Every row carries the fit's 95% interval, checked against scales drawn from the covariance: the
    // linearised half-width matches the spread of the re-timed values.
    const MachineFreedom& f = report.freedom[0];
    ASSERT_EQ(f.free_keys.size(), 3u);
    ASSERT_EQ(f.log_covariance.size(), 9u);
    std::array<double, 9> c{};
    std::copy(f.log_covariance.begin(), f.log_covariance.end(), c.begin());
    // Cholesky factor of the 3x3 covariance.
    std::array<double, 9> l{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j <= i; ++j) {
            double sum = c[static_cast<std::size_t>(3 * i + j)];
            for (int k = 0; k < j; ++k)
                sum -= l[static_cast<std::size_t>(3 * i + k)] * l[static_cast<std::size_t>(3 * j + k)];
            l[static_cast<std::size_t>(3 * i + j)] =
                i == j ? std::sqrt(sum) : sum / l[static_cast<std::size_t>(3 * j + j)];
        }
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    const TargetResult& row = report.results.front();
    ASSERT_TRUE(row.low && row.high);
    EXPECT_LT(*row.low, row.simulated);
    EXPECT_GT(*row.high, row.simulated);
    const Target* target = &model.targets().targets.front();
    std::vector<double> logs;
    for (int draw = 0; draw < 60; ++draw) {
        const std::array<double, 3> z{normal(random), normal(random), normal(random)};
        CalibrationScales s = fitted;
        double* const members[] = {&s.gp_flops, &s.gp_cycles, &s.pp_cycles};
        for (int i = 0; i < 3; ++i) {
            double shift = 0;
            for (int k = 0; k <= i; ++k)
                shift += l[static_cast<std::size_t>(3 * i + k)] * z[static_cast<std::size_t>(k)];
            *members[i] *= std::exp(shift);
        }
        logs.push_back(std::log(model.simulate(files.machine.string(), s, {target}).front()));
    }
    double mean = 0, square = 0;
    for (const double v : logs) mean += v / static_cast<double>(logs.size());
    for (const double v : logs) square += (v - mean) * (v - mean) / static_cast<double>(logs.size() - 1);
    const double linearised = std::log(*row.high / row.simulated) / 1.959964;
    EXPECT_NEAR(std::sqrt(square) / linearised, 1.0, 0.3);

    // The fitted machine file carries the values and loads as a machine, under a header of its own
    // that says what it was fitted to and how well.
    const std::string text = fitted_machine_file(model, report, files.machine.string());
    const std::string stem = files.machine.stem().string();
    EXPECT_EQ(text.rfind("# " + stem + "-fitted: the " + stem + " machine with its calibration.* scales fitted", 0), 0u)
        << text;
    EXPECT_NE(text.find(set.file.string()), std::string::npos) << text;
    EXPECT_NE(text.find("Targets within 10%: 7 of 7 fitted, 0 of 0 workload rows, 1 of 1 predicted"), std::string::npos)
        << text;
    const std::filesystem::path fitted_file = files.dir / "tiny-fitted.toml";
    std::ofstream(fitted_file) << text;
    const MachineConfig reloaded = load_run_config(fitted_file.string(), {});
    EXPECT_NEAR(reloaded.real("calibration.gp_flops_scale"), fitted.gp_flops, 1e-5 * fitted.gp_flops);
    EXPECT_EQ(reloaded.machine_name(), "tiny-fitted");
    EXPECT_DOUBLE_EQ(reloaded.real("calibration.gp_flops_scale_max"), 10.0);
}

TEST(Fit, TheSameAtOneAndTwoThreads) {
    // The Jacobian's simulations, the scales' sensitivities and the leave-one-out refits run side by side.
    const test::CalibrationFiles files = test::write_calibration_files("threads");
    const TargetSet set = synthetic_targets(files, CalibrationScales{0.7, 2.5, 0.9});
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    FitOptions options;
    options.leave_one_out = true;
    const auto fitted_with = [&](std::size_t threads) {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        nlohmann::json report = fit_targets(model, options).to_json();
        report.erase("host_seconds");
        return report;
    };
    const nlohmann::json one = fitted_with(1);
    EXPECT_EQ(one, fitted_with(2));
    EXPECT_FALSE(one["parameters"].empty());
}

TEST(Fit, FreesFewerScalesThanHalfItsTargets) {
    const test::CalibrationFiles files = test::write_calibration_files("parsimony");
    TargetSet set = synthetic_targets(files, CalibrationScales{1.8, 0.6, 1.3});
    set.targets.resize(5);  // four fitted rows and the held-out one: room for one free scale
    set.targets.back().use = TargetUse::Predict;
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    FitOptions options;
    options.leave_one_out = false;
    const FitReport report = fit_targets(model, options);
    int free = 0;
    for (const FittedParameter& p : report.parameters) {
        free += p.free;
        if (!p.free) {
            EXPECT_FALSE(p.note.empty()) << p.key;
        }
    }
    EXPECT_EQ(free, 1);
    const bool any_held_for_parsimony = std::any_of(
        report.parameters.begin(), report.parameters.end(),
        [](const FittedParameter& p) { return p.note.find("allow at most 1 free scale") != std::string::npos; });
    EXPECT_TRUE(any_held_for_parsimony);
}

// The machine file's own range bounds each scale; a scale the targets push past it stays at the bound,
// and the report says so as a finding, quoting where the range comes from.
TEST(Fit, AScaleHeldAtItsMachinesBoundIsReportedAsAFinding) {
    const test::CalibrationFiles files = test::write_calibration_files("bounded");
    TargetSet set = synthetic_targets(files, CalibrationScales{1.8, 0.6, 1.3});
    std::ofstream(files.machine, std::ios::app) << "\n[calibration]\npp_cycles_scale_max = 1.1\n"
                                                   "pp_cycles_scale_bounds_why = \"a test's range\"\n";
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    FitOptions options;
    options.leave_one_out = false;
    const FitReport report = fit_targets(model, options);
    const auto pp = std::find_if(report.parameters.begin(), report.parameters.end(),
                                 [](const FittedParameter& p) { return p.key == "calibration.pp_cycles_scale"; });
    ASSERT_NE(pp, report.parameters.end());
    EXPECT_DOUBLE_EQ(pp->upper, 1.1);
    EXPECT_NEAR(pp->value, 1.1, 1e-6);
    EXPECT_TRUE(pp->at_bound);
    EXPECT_NE(pp->note.find("at its upper bound, a finding"), std::string::npos) << pp->note;
    EXPECT_NE(pp->note.find("a test's range"), std::string::npos) << pp->note;
    EXPECT_NE(report.to_markdown().find("[1, 1.1]: a test's range"), std::string::npos);
}

TEST(Fit, AnEmptyRangeForAScaleIsRefusedNamingTheField) {
    const test::CalibrationFiles files = test::write_calibration_files("empty_range");
    TargetSet set = synthetic_targets(files, CalibrationScales{});
    std::ofstream(files.machine, std::ios::app)
        << "\n[calibration]\ngp_flops_scale_min = 3.0\ngp_flops_scale_max = 2.0\n";
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    try {
        (void)fit_targets(model, FitOptions{});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), files.machine.string());
        EXPECT_EQ(e.field(), "calibration.gp_flops_scale_min");
        EXPECT_NE(std::string(e.what()).find("must be below"), std::string::npos) << e.what();
    }
}

TEST(Fit, NeedsMoreFittedTargetsThanFreeScales) {
    const test::CalibrationFiles files = test::write_calibration_files("too_few");
    TargetSet set;
    set.file = files.dir / "few.toml";
    set.name = "few";
    set.targets = {make_target(files, "orbit-refined", 1, "refined_seconds"),
                   make_target(files, "first-pp", 0, "pp_seconds")};
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    try {
        (void)fit_targets(model, FitOptions{});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "targets");
        EXPECT_NE(std::string(e.what()).find("needs at least 3"), std::string::npos) << e.what();
    }
}

// A target file with one row, `field` replaced by `value` (a TOML value, or nothing to drop it).
std::filesystem::path target_file(const test::CalibrationFiles& files, const std::string& field,
                                  const std::string& value) {
    std::map<std::string, std::string> row{{"id", "\"a\""},
                                           {"source", "\"test\""},
                                           {"scenario", "\"" + files.scenario.string() + "\""},
                                           {"frame", "1"},
                                           {"machine", "\"" + files.machine.string() + "\""},
                                           {"metric", "\"crude_seconds\""},
                                           {"reported", "0.1"},
                                           {"exactness", "\"estimate\""},
                                           {"use", "\"fit\""}};
    row[field] = value;
    const std::filesystem::path path = files.dir / ("targets-" + field + ".toml");
    std::ofstream out(path);
    out << "[[targets]]\n";
    for (const auto& [k, v] : row)
        if (!v.empty()) out << k << " = " << v << "\n";
    return path;
}

TEST(Targets, BadRowsNameTheFieldAndTheReason) {
    const test::CalibrationFiles files = test::write_calibration_files("bad_targets");
    const auto expect_error = [&](const std::string& field, const std::string& value, const std::string& reason) {
        const std::filesystem::path path = target_file(files, field, value);
        try {
            (void)load_targets(path);
            ADD_FAILURE() << field << " = " << value << " was accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), path.string());
            EXPECT_EQ(e.field(), "targets[0]." + field) << e.what();
            EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
        }
    };
    expect_error("scenario", "\"no-such-scenario\"", "no-such-scenario");
    expect_error("metric", "\"frames_per_fortnight\"", "unknown metric");
    expect_error("frame", "7", "0 to 2");
    expect_error("machine", "\"no-such-machine\"", "no-such-machine");
    expect_error("reported", "-1.0", "positive");
    expect_error("exactness", "\"roughly\"", "measured, estimate or order-of-magnitude");
    expect_error("use", "\"maybe\"", "fit, held-out, check, by-construction or comparison");
    expect_error("use", "\"check\"", "for formula rows");
    expect_error("id", "", "is missing");
    expect_error("divided_by_frame", "9", "0 to 2");
    expect_error("divided_by_frame", "1", "must differ");
    // And the good row loads.
    const TargetSet good = load_targets(target_file(files, "id", "\"fine\""));
    ASSERT_EQ(good.targets.size(), 1u);
    EXPECT_EQ(good.targets[0].metric, "crude_seconds");
    EXPECT_EQ(good.targets[0].frame, 1);
}

TEST(Targets, ARatioRowIsOneFramesMetricOverAnothers) {
    const test::CalibrationFiles files = test::write_calibration_files("ratio");
    const Target ratio = load_targets(target_file(files, "divided_by_frame", "0")).targets.at(0);
    EXPECT_EQ(ratio.unit, "ratio");
    TargetSet set;
    set.file = files.dir / "ratio.toml";
    set.targets = {make_target(files, "orbit-crude", 1, "crude_seconds"),
                   make_target(files, "first-crude", 0, "crude_seconds"), ratio};
    const CalibrationModel model(set, load_run_config(files.machine.string(), {}));
    const std::vector<const Target*> rows{&set.targets[0], &set.targets[1], &set.targets[2]};
    const std::vector<double> values = model.simulate(files.machine.string(), CalibrationScales{}, rows);
    ASSERT_EQ(values.size(), 3u);
    EXPECT_GT(values[1], 0.0);
    EXPECT_DOUBLE_EQ(values[2], values[0] / values[1]);
}

TEST(Targets, FiguresShowFramesTheTargetsRecord) {
    const test::CalibrationFiles files = test::write_calibration_files("figures");
    const std::filesystem::path path = target_file(files, "id", "\"fine\"");
    const auto with_figure = [&](const std::string& figure) {
        const std::filesystem::path out = files.dir / "targets-figures.toml";
        std::ofstream(out) << pp5::test::read_file(path) << "\n[[figures]]\n" << figure;
        return out;
    };
    const TargetSet good = load_targets(with_figure("name = \"crude\"\nscenario = \"" + files.scenario.string() +
                                                    "\"\nframe = 1\npicture = \"first\"\n"));
    ASSERT_EQ(good.figures.size(), 1u);
    EXPECT_EQ(good.figures[0].name, "crude");
    EXPECT_FALSE(good.figures[0].final);
    const auto expect_error = [&](const std::string& figure, const std::string& field) {
        try {
            (void)load_targets(with_figure(figure));
            ADD_FAILURE() << figure << " was accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), field) << e.what();
        }
    };
    expect_error("name = \"late\"\nscenario = \"" + files.scenario.string() + "\"\nframe = 3\n",
                 "figures[0].frame");  // it has frames 0 to 2
    expect_error("name = \"late\"\nscenario = \"no-such-scenario\"\n", "figures[0].scenario");
    // A frame no target times is recorded for its picture.
    const TargetSet pictured =
        load_targets(with_figure("name = \"late\"\nscenario = \"" + files.scenario.string() + "\"\nframe = 2\n"));
    const CalibrationModel model(pictured);
    EXPECT_EQ(model.recording(files.scenario.string()).frames().size(), 3u);
    expect_error("name = \"../up\"\nscenario = \"" + files.scenario.string() + "\"\n", "figures[0].name");
    expect_error("name = \"x\"\nscenario = \"" + files.scenario.string() + "\"\npicture = \"middle\"\n",
                 "figures[0].picture");
    expect_error("name = \"x\"\nscenario = \"" + files.scenario.string() + "\"\ncolour = 1\n", "figures[0].colour");
}

// The ids of a shipped file's rows with one use, in file order.
std::vector<std::string> rows_with_use(const TargetSet& set, TargetUse use) {
    std::vector<std::string> ids;
    for (const Target& t : set.targets)
        if (t.use == use) ids.push_back(t.id);
    return ids;
}

TEST(Targets, TheShippedLevoyFileLoads) {
    const TargetSet set = load_targets(resolve_targets_file(kDefaultTargets));
    EXPECT_GE(set.targets.size(), 14u);
    EXPECT_EQ(set.figures.size(), 5u);
    int sun = 0;
    for (const Target& t : set.targets) sun += t.machine == "sun4-280";
    EXPECT_EQ(sun, 3);  // Levoy's three Sun 4/280 measurements
    // Which rows the predicted totals count: the Pixel-planes 5 estimates the fit never sees.
    EXPECT_EQ(rows_with_use(set, TargetUse::Predict),
              (std::vector<std::string>{"region-crude", "region-refined", "classification-crude",
                                        "classification-refined", "set-change-crude"}));
    // The Sun rows are fitted, after the workload step has matched their ratios.
    for (const WorkloadSpec& w : set.workload)
        for (const std::string& id : {w.numerator, w.denominator})
            EXPECT_EQ(set.find(id)->machine, "sun4-280") << w.key;
}

TEST(Targets, FormulaRowsAreAKernelsFigureFromItsInputs) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("pp5_formula_rows_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto file_with = [&](const std::string& row) {
        const std::filesystem::path path = dir / "formula.toml";
        std::ofstream(path) << "[[targets]]\nid = \"argon\"\nsource = \"Wilson et al. 2002\"\n" << row;
        return path;
    };
    const std::string good =
        "kernel = \"wilson\"\nformula = \"storage_megabytes\"\n"
        "inputs = { low_resolution = [256, 256, 256], points = 361000, error_grid = [512, 512, 512] }\n"
        "reported = 37.0\nexactness = \"estimate\"\nuse = \"check\"\n";
    const TargetSet set = load_targets(file_with(good));
    ASSERT_TRUE(set.targets.at(0).is_formula());
    EXPECT_EQ(set.targets[0].unit, "MB");
    // Only formula rows: nothing is rendered, and the value is the kernel's arithmetic.
    const CalibrationModel model(set);
    EXPECT_NEAR(model.formula_value(set.targets[0]), 36.803432, 1e-6);
    const FitReport report = evaluate_targets(model, {});
    ASSERT_EQ(report.results.size(), 1u);
    EXPECT_NEAR(report.results[0].relative_error, 36.803432 / 37.0 - 1, 1e-6);
    const auto expect_error = [&](const std::string& row, const std::string& field) {
        try {
            (void)load_targets(file_with(row));
            ADD_FAILURE() << row << " was accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), field) << e.what();
        }
    };
    const auto replace = [&](std::string text, const std::string& from, const std::string& to) {
        return text.replace(text.find(from), from.size(), to);
    };
    expect_error(replace(good, "\"check\"", "\"fit\""), "targets[0].use");
    expect_error(replace(good, "\"check\"", "\"held-out\""), "targets[0].use");
    expect_error(replace(good, "storage_megabytes", "volume"), "targets[0].formula");
    expect_error(replace(good, "kernel = \"wilson\"", "kernel = \"nobody\""), "targets[0].kernel");
    expect_error(replace(good, "points = 361000", "points = -5"), "targets[0].inputs");
    expect_error(replace(good, "points = 361000, ", ""), "targets[0].inputs.points");
    expect_error(replace(good, "points = 361000", "pointz = 361000"), "targets[0].inputs.pointz");
    // Each input has its declared length, checked for every kernel's formulas alike.
    expect_error(replace(good, "[256, 256, 256]", "[256, 256]"), "targets[0].inputs.low_resolution");
    expect_error(replace(good, "points = 361000", "points = [361000, 5]"), "targets[0].inputs.points");
    const std::string perm_row =
        "kernel = \"perm\"\nformula = \"memory_megabytes\"\n"
        "inputs = { dims = [256, 256, 113], candidates = 900000, density_positions = 8, gradient_positions = 8, "
        "index_bytes = 2, density_bytes = 1 }\nreported = 6.0\nexactness = \"estimate\"\nuse = \"check\"\n";
    EXPECT_NO_THROW(load_targets(file_with(perm_row)));
    expect_error(replace(perm_row, "candidates = 900000", "candidates = [900000, 1]"), "targets[0].inputs.candidates");
    expect_error(good + "scenario = \"mr-head\"\n", "targets[0].scenario");
    std::filesystem::remove_all(dir);
}

TEST(Targets, TheShippedWilsonFileLoads) {
    const TargetSet set = load_targets(resolve_targets_file("wilson02"));
    int formulas = 0;
    for (const Target& t : set.targets) formulas += t.is_formula();
    EXPECT_EQ(formulas, 12);
    EXPECT_EQ(rows_with_use(set, TargetUse::Check).size(), 12u);  // the paper's equations recomputed
    EXPECT_EQ(rows_with_use(set, TargetUse::Predict), (std::vector<std::string>{"threshold-trend-mr-head"}));
    EXPECT_EQ(set.figures.size(), 2u);
}

TEST(Targets, TheShippedLimShinFileLoadsAndMatchesBothTables) {
    const TargetSet set = load_targets(resolve_targets_file("lim-shin"));
    const CalibrationModel model(set);
    const FitReport report = evaluate_targets(model, {});
    ASSERT_EQ(report.results.size(), 10u);
    // Tables 1 and 2 print whole megabytes: every row rounds to what is printed.
    for (const TargetResult& r : report.results)
        EXPECT_EQ(std::lround(r.simulated), std::lround(r.target.reported)) << r.target.id;
}

TEST(Targets, TheShippedYuanFileLoads) {
    const TargetSet set = load_targets(resolve_targets_file("yuan03"));
    int ratios = 0;
    for (const Target& t : set.targets) {
        EXPECT_FALSE(t.fitted()) << t.id;  // nothing here calibrates the machines
        ratios += t.divided_by_frame >= 0;
    }
    // The view distance of the mixed view was chosen to give the paper's splat fraction; the Pixel-planes 5
    // rows are the paper's P4 ratios beside another machine's. Neither is a prediction.
    EXPECT_EQ(rows_with_use(set, TargetUse::ByConstruction),
              (std::vector<std::string>{"checker-mixed-splat-fraction"}));
    EXPECT_EQ(rows_with_use(set, TargetUse::Comparison),
              (std::vector<std::string>{"checker-splat-point-ratio-pxpl5", "checker-mixed-point-ratio-pxpl5",
                                        "skull-splat-point-ratio-pxpl5"}));
    EXPECT_EQ(rows_with_use(set, TargetUse::Predict).size(), 9u);
    EXPECT_GE(ratios, 4);
    EXPECT_EQ(set.figures.size(), 3u);
}

}  // namespace
}  // namespace pp5

namespace pp5 {
namespace {

TEST(HostCheck, RecoversTheScalesOfSyntheticMeasurementsAndPredictsTheHeldOutHalf) {
    HostCheckReport report;
    for (int i = 0; i < 8; ++i) {
        HostCase c;
        c.fitted = i % 2 == 0;
        c.flop_seconds = 0.01 * (1 + i);
        c.cycle_seconds = 0.004 * (8 - i) * (8 - i);
        c.measured_seconds = 0.45 * c.flop_seconds + 3.5 * c.cycle_seconds;
        report.cases.push_back(c);
    }
    fit_host_cases(report);
    EXPECT_NEAR(report.gp_flops_scale, 0.45, 1e-6);
    EXPECT_NEAR(report.gp_cycles_scale, 3.5, 1e-5);
    EXPECT_LT(report.median_held_out_error, 1e-6);
    for (const HostCase& c : report.cases) EXPECT_NEAR(c.predicted_seconds, c.measured_seconds, 1e-9);
}

}  // namespace
}  // namespace pp5
