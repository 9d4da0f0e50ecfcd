// The workload step: a functional parameter found from the ratio of two measured rows. It recovers the
// ratio its rows were made with, keeps a bound it cannot get past (and says so), sets the value on every
// machine the model records and times with, and refuses [[workload]] rows that could bias the fit.

#include "calibration/workload.h"
#include "calibration/fit.h"
#include "calibration/targets.h"
#include "calibration/timing_model.h"
#include "calibration_support.h"
#include "kernels/registry/run_config.h"
#include "sim/core/input_error.h"
#include "tests/support/run_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace pp5 {
namespace {

// The observer moved (frame 1): a crude pass, then refinement.
Target row(const test::CalibrationFiles& files, const std::string& id, const std::string& metric) {
    return test::make_target(files, id, 1, metric);
}

// Refinement over crude time on the tiny machine, with the refinement threshold at `threshold`.
TargetSet refinement_rows(const test::CalibrationFiles& files, double threshold) {
    TargetSet set;
    set.file = files.dir / "workload.toml";
    set.name = "workload";
    set.targets = {row(files, "refinement", "refinement_seconds"), row(files, "crude", "crude_seconds")};
    const CalibrationModel generator(set, std::nullopt, {{"levoy.refinement_threshold", threshold, false}});
    const std::vector<double> v =
        generator.simulate(files.machine.string(), CalibrationScales{},
                           {&generator.targets().targets[0], &generator.targets().targets[1]});
    set.targets[0].reported = v[0];
    set.targets[1].reported = v[1];
    set.workload.push_back({"levoy.refinement_threshold", 0.0, 0.4, false, "refinement", "crude", "synthetic"});
    return set;
}

TEST(Workload, FindsTheValueWhoseRatioTheRowsWereMadeWith) {
    const test::CalibrationFiles files = test::write_calibration_files("workload_recover");
    const TargetSet set = refinement_rows(files, 0.03);
    const std::vector<IdentifiedWorkload> found = identify_workload(set, {});
    ASSERT_EQ(found.size(), 1u);
    const IdentifiedWorkload& w = found[0];
    EXPECT_FALSE(w.at_bound) << w.note;
    EXPECT_NEAR(w.simulated_ratio / w.reported_ratio, 1.0, 0.005);
    // The ratio is a step function of the threshold (a square splits or not), so any value on the
    // step gives it: the one found must reproduce the rows, and lie well away from the file's 0.1.
    EXPECT_LT(w.value, 0.08);
    EXPECT_DOUBLE_EQ(std::get<double>(w.machine_value), 0.1);
    EXPECT_LE(w.trials, 16);

    // The model then records and times with it on every machine.
    const CalibrationModel model(set, std::nullopt, workload_settings(found));
    EXPECT_DOUBLE_EQ(model.base_config(files.machine.string()).real("levoy.refinement_threshold"), w.value);
    const std::vector<double> v = model.simulate(files.machine.string(), CalibrationScales{},
                                                 {&model.targets().targets[0], &model.targets().targets[1]});
    EXPECT_NEAR(v[0] / v[1], w.simulated_ratio, 1e-9 * w.simulated_ratio);
}

TEST(Workload, ARatioOutsideTheBoundsKeepsTheNearerBoundAndSaysSo) {
    const test::CalibrationFiles files = test::write_calibration_files("workload_bound");
    TargetSet set = refinement_rows(files, 0.03);
    set.targets[0].reported *= 1000.0;  // far more refinement than any threshold gives
    const std::vector<IdentifiedWorkload> found = identify_workload(set, {});
    ASSERT_EQ(found.size(), 1u);
    EXPECT_TRUE(found[0].at_bound);
    EXPECT_DOUBLE_EQ(found[0].value, 0.0);  // the lowest threshold refines most
    EXPECT_NE(found[0].note.find("outside"), std::string::npos) << found[0].note;
}

TEST(Workload, TheFittedMachineFileCarriesTheIdentifiedValues) {
    const test::CalibrationFiles files = test::write_calibration_files("workload_file");
    const TargetSet set = refinement_rows(files, 0.03);
    FitReport report;
    report.workload = identify_workload(set, {});
    const CalibrationModel model(set, std::nullopt, workload_settings(report.workload));
    const std::filesystem::path fitted = files.dir / "tiny-fitted.toml";
    std::ofstream(fitted) << fitted_machine_file(model, report, files.machine.string());
    const MachineConfig config = load_run_config(fitted.string(), {});
    EXPECT_NEAR(config.real("levoy.refinement_threshold"), report.workload[0].value, 1e-5);
}

// Leaving out a row the workload step used runs the step again without it: its parameter falls back to
// the machine file's value, so the prediction never saw the row. The machine's degrees of freedom count
// the workload parameter beside the scale.
TEST(Workload, LeaveOneOutIdentifiesTheWorkloadAgainWithoutTheRow) {
    const test::CalibrationFiles files = test::write_calibration_files("workload_loo");
    TargetSet set = refinement_rows(files, 0.03);
    Target third = row(files, "still", "crude_seconds");  // a third fitted row, so that one scale may be free
    third.frame = 2;
    {
        const CalibrationModel generator(TargetSet{set.file, set.name, {}, {third}, {}, {}}, std::nullopt,
                                         {{"levoy.refinement_threshold", 0.03, false}});
        third.reported =
            generator.simulate(files.machine.string(), CalibrationScales{}, {&generator.targets().targets[0]}).front();
    }
    set.targets.push_back(third);
    const std::vector<IdentifiedWorkload> found = identify_workload(set, {});
    const CalibrationModel model(set, std::nullopt, workload_settings(found));
    FitReport report = fit_targets(model, {});
    report.workload = found;

    ASSERT_EQ(report.freedom.size(), 1u);
    EXPECT_EQ(report.freedom[0].rows, 3);
    EXPECT_EQ(report.freedom[0].workload_parameters, 1);
    EXPECT_EQ(report.freedom[0].degrees_of_freedom(), 3 - report.freedom[0].free_scales - 1);
    for (const TargetResult& r : report.results) {
        EXPECT_EQ(report.group_of(r.target), r.target.id == "still" ? RowGroup::Fitted : RowGroup::Workload)
            << r.target.id;
        ASSERT_TRUE(r.leave_one_out.has_value()) << r.target.id << ": " << r.leave_one_out_note;
        if (r.target.id == "still") {
            EXPECT_EQ(r.leave_one_out_note.find("workload"), std::string::npos) << r.leave_one_out_note;
            continue;
        }
        EXPECT_NE(r.leave_one_out_note.find("levoy.refinement_threshold at the machine file's value"),
                  std::string::npos)
            << r.target.id << ": " << r.leave_one_out_note;
    }
    // Without its ratio the threshold is the file's 0.1, which refines far less than the 0.03 the rows
    // were made with: the refinement row's honest prediction misses it.
    const auto refinement = std::find_if(report.results.begin(), report.results.end(),
                                         [](const TargetResult& r) { return r.target.id == "refinement"; });
    EXPECT_LT(*refinement->leave_one_out_error, -0.1) << *refinement->leave_one_out;
}

std::filesystem::path workload_file(const test::CalibrationFiles& files, const std::string& workload) {
    const std::filesystem::path path = files.dir / "targets-workload.toml";
    std::ofstream out(path);
    for (const auto& [id, exactness, machine] :
         {std::tuple{"a", "measured", files.machine.string()}, std::tuple{"b", "measured", files.machine.string()},
          std::tuple{"c", "estimate", files.machine.string()}, std::tuple{"d", "measured", std::string("pxpl5")}}) {
        out << "[[targets]]\nid = \"" << id << "\"\nsource = \"test\"\nscenario = \"" << files.scenario.string()
            << "\"\nframe = 1\nmachine = \"" << machine
            << "\"\nmetric = \"crude_seconds\"\nreported = 0.1\nexactness = \"" << exactness << "\"\nuse = \"fit\"\n\n";
    }
    out << "[[workload]]\n" << workload;
    return path;
}

TEST(Workload, RowsThatCouldBiasTheFitAreRefused) {
    const test::CalibrationFiles files = test::write_calibration_files("workload_bad");
    const std::string good =
        "parameter = \"levoy.refinement_threshold\"\nbounds = [0.0, 0.5]\nratio_of = [\"a\", \"b\"]\nwhy = \"test\"\n";
    EXPECT_EQ(load_targets(workload_file(files, good)).workload.size(), 1u);
    const auto expect_error = [&](const std::string& text, const std::string& field, const std::string& reason) {
        const std::filesystem::path path = workload_file(files, text);
        try {
            (void)load_targets(path);
            ADD_FAILURE() << text << " was accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.file(), path.string());
            EXPECT_EQ(e.field(), "workload[0]." + field) << e.what();
            EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
        }
    };
    const auto with = [&](const std::string& from, const std::string& to) {
        std::string text = good;
        text.replace(text.find(from), from.size(), to);
        return text;
    };
    expect_error(with("levoy.refinement_threshold", "levoy.no_such_thing"), "parameter",
                 "not a machine or kernel parameter");
    expect_error(with("levoy.refinement_threshold", "calibration.gp_flops_scale"), "parameter", "only changes timing");
    expect_error(with("levoy.refinement_threshold", "levoy.ray_assignment"), "parameter", "not a number");
    expect_error(with("[0.0, 0.5]", "[0.5, 0.0]"), "bounds", "lower < upper");
    expect_error(with("[0.0, 0.5]", "[-2.0, 0.5]"), "bounds", "own range");
    expect_error(with("[\"a\", \"b\"]", "[\"a\", \"c\"]"), "ratio_of", "never from an estimate");
    expect_error(with("[\"a\", \"b\"]", "[\"a\", \"d\"]"), "ratio_of", "one machine");
    expect_error(with("[\"a\", \"b\"]", "[\"a\", \"zz\"]"), "ratio_of", "no target has the id");
    expect_error(with("[\"a\", \"b\"]", "[\"a\", \"a\"]"), "ratio_of", "two different targets");
    expect_error(good + "step = 2\n", "step", "unknown field");
    expect_error(with("parameter = \"levoy.refinement_threshold\"\nbounds = [0.0, 0.5]",
                      "parameter = \"levoy.jitter_samples\"\nbounds = [1.5, 4]"),
                 "bounds", "whole numbers");
}

TEST(Workload, TheShippedLevoyFileIdentifiesItsTwoFromTheSunMeasurementsOnly) {
    const TargetSet set = load_targets(resolve_targets_file(kDefaultTargets));
    ASSERT_EQ(set.workload.size(), 2u);
    for (const WorkloadSpec& w : set.workload) {
        for (const std::string& id : {w.numerator, w.denominator}) {
            const Target* t = set.find(id);
            ASSERT_NE(t, nullptr) << id;
            EXPECT_EQ(t->machine, "sun4-280") << id;
            EXPECT_EQ(t->exactness, Exactness::Measured) << id;
        }
    }
}

}  // namespace
}  // namespace pp5
