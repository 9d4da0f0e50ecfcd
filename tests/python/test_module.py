"""The pp5sim Python module: scenarios and machines through the CLI's loaders, renders as NumPy arrays
and nested dicts, re-timing a recording on another machine, the browser tool's view, and InputError
carrying the CLI's file, field and reason. Run by ctest with build/python on PYTHONPATH."""

import unittest

import numpy as np
import pp5sim

SMALL = """
[scenario]
name = "python-test"
[dataset]
phantom = "sphere"
size = 24
[image]
width = 32
height = 32
[classification]
kind = "piecewise-linear"
points = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, opacity = 0.8 }]
[shading]
specular = 0.0
light_direction = [0.4, 1.0, 0.5]
[[frames]]
label = "first"
[[frames]]
label = "orbit"
camera = { azimuth = 30.0 }
"""


class ModuleTest(unittest.TestCase):
    def test_lists_the_shipped_scenarios_and_kernels(self):
        self.assertIn("mr-head", pp5sim.scenarios())
        names = [k["name"] for k in pp5sim.kernels()]
        for name in ("levoy", "yuan", "wilson", "perm", "reference"):
            self.assertIn(name, names)

    def test_renders_frames_as_arrays_with_stats_and_config(self):
        scenario = pp5sim.scenario_from_toml(SMALL)
        self.assertEqual(scenario.frame_labels, ["first", "orbit"])
        run = pp5sim.render(scenario)
        self.assertEqual(len(run.frames), 2)
        frame = run.frames[1]
        self.assertEqual(frame.image.shape, (32, 32, 4))
        self.assertEqual(frame.image.dtype, np.float32)
        self.assertGreater(float(frame.image[..., :3].max()), 0.1)  # the sphere is there
        self.assertGreaterEqual(len(frame.passes), 1)
        np.testing.assert_array_equal(frame.passes[-1], frame.image)
        self.assertAlmostEqual(frame.simulated_seconds, run.stats["frames"][1]["simulated_seconds"])
        self.assertEqual(frame.record["label"], "orbit")
        self.assertFalse(frame.record["changed"]["lighting"])
        self.assertGreater(frame.utilisation["gps"], 0.0)
        # Statistics carry units and descriptions, as stats.json does.
        gp = run.stats["components"]["gp[0]"]
        busy = gp["busy_time"]
        self.assertEqual(busy["unit"], "ps")
        self.assertTrue(busy["description"])
        self.assertEqual(run.config["parameters"]["gp.count"]["value"], 32)

    def test_the_same_inputs_give_the_same_picture(self):
        scenario = pp5sim.scenario_from_toml(SMALL)
        a = pp5sim.render(scenario, frames=1)
        b = pp5sim.render(scenario, frames=1)
        np.testing.assert_array_equal(a.frames[0].image, b.frames[0].image)
        self.assertEqual(a.frames[0].simulated_seconds, b.frames[0].simulated_seconds)

    def test_a_recording_retimes_as_a_fresh_render_would(self):
        scenario = pp5sim.scenario_from_toml(SMALL)
        recording = pp5sim.record(scenario)
        faster_ring = pp5sim.Machine("pxpl5", {"gp.count": 8})
        retimed = recording.time_on(faster_ring)
        fresh = pp5sim.render(scenario, machine=faster_ring)
        self.assertEqual(len(retimed), 2)
        for timed, rendered in zip(retimed, fresh.frames):
            self.assertAlmostEqual(timed.simulated_seconds, rendered.simulated_seconds, places=12)
            self.assertAlmostEqual(timed.frames_per_second, 1 / rendered.simulated_seconds)
            self.assertIn("refined_seconds", timed.metrics)
            self.assertEqual(timed["simulated_seconds"], timed.simulated_seconds)  # read as the dict it was, too
            self.assertIn("gp.count=8", timed.machine)
        self.assertEqual(retimed[-1].label, retimed[len(retimed) - 1].label)
        with self.assertRaises(IndexError):
            retimed[2]
        with self.assertRaises(KeyError):
            retimed[0]["no_such_field"]
        stock = recording.time_on(pp5sim.Machine())
        self.assertGreater(retimed[0].simulated_seconds, stock[0].simulated_seconds)

    def test_retimings_make_a_table(self):
        try:
            import pandas
        except ImportError:
            self.skipTest("no pandas (the setup script installs Debian's python3-pandas)")
        recording = pp5sim.record(pp5sim.scenario_from_toml(SMALL))
        tables = [recording.time_on(pp5sim.Machine("pxpl5", {"gp.count": g})).to_dataframe() for g in (4, 16)]
        table = pandas.concat(tables, ignore_index=True)
        self.assertEqual(len(table), 4)
        self.assertEqual(list(table.columns[:4]), ["label", "machine", "simulated_seconds", "frames_per_second"])
        self.assertIn("phase.ray_casting", table.columns)
        self.assertIn("refined_seconds", table.columns)
        four = table[table.machine.str.contains("gp.count=4")]
        sixteen = table[table.machine.str.contains("gp.count=16")]
        self.assertTrue((four.simulated_seconds.values > sixteen.simulated_seconds.values).all())

    def test_machines_set_parameters_and_refuse_bad_ones(self):
        machine = pp5sim.Machine("pxpl5", {"gp.count": 64, "ring.clock_mhz": 80.0})
        self.assertEqual(machine["gp.count"], 64)
        self.assertEqual(machine.with_set({"gp.count": 16})["gp.count"], 16)
        with self.assertRaises(pp5sim.InputError) as caught:
            pp5sim.Machine("pxpl5", {"gp.count": -3})
        self.assertEqual(caught.exception.field, "gp.count")
        self.assertIn("range", caught.exception.reason)
        with self.assertRaises(pp5sim.InputError) as caught:
            pp5sim.Machine("pxpl5", {"gp.no_such_thing": 1})
        self.assertIn("gp.no_such_thing", str(caught.exception))

    def test_bad_scenarios_name_their_field(self):
        with self.assertRaises(pp5sim.InputError) as caught:
            pp5sim.scenario_from_toml(SMALL.replace("size = 24", "size = -1"))
        self.assertEqual(caught.exception.field, "dataset.size")
        self.assertTrue(caught.exception.file.endswith("<python>.toml"))
        with self.assertRaises(ValueError):  # InputError is a ValueError
            pp5sim.load_scenario("no-such-scenario")

    def test_the_view_recomputes_only_what_a_change_needs(self):
        view = pp5sim.View(pp5sim.scenario_from_toml(SMALL))
        view.apply({"light": {"direction": [-0.6, 1.0, 0.3]}})
        phases = {p["name"]: p["ran"] for p in view.state["frame"]["phases"]}
        self.assertTrue(phases["shading"])
        self.assertFalse(phases["pyramid"])
        self.assertEqual(view.png[1:4], b"PNG")
        with self.assertRaises(pp5sim.InputError) as caught:
            view.apply({"camera": {"elevation": 120}})
        self.assertEqual(caught.exception.field, "camera.elevation")

    def test_the_view_does_what_the_page_does(self):
        view = pp5sim.View(pp5sim.scenario_from_toml(SMALL))
        gps = next(c["value"] for c in view.state["machine_parameters"] if c["key"] == "gp.count")
        timeline = view.timeline(bins=50)
        self.assertEqual(sum(lane["group"] == "GPs" for lane in timeline["lanes"]), gps)
        self.assertEqual(len(timeline["lanes"][0]["busy"]), 50)
        self.assertEqual(view.tile_map_png[1:4], b"PNG")
        view.apply({"machine": {"gp.count": 2}})  # re-timed: the timeline follows
        self.assertEqual(sum(lane["group"] == "GPs" for lane in view.timeline()["lanes"]), 2)
        view.apply({"light": {"stationary": [{"direction": [-1.0, 0.2, 0.3], "intensity": 0.6}]}})
        self.assertEqual(len(view.state["light"]["stationary"]), 1)
        report = view.compare_kernels()
        self.assertIn("levoy", [row["kernel"] for row in report["kernels"]])
        with self.assertRaises(pp5sim.InputError):
            view.timeline(bins=0)

    def test_a_scenario_can_be_named_as_on_the_command_line(self):
        run = pp5sim.render("sphere")
        self.assertEqual(run.stats["summary"]["scenario"], "sphere")
        with self.assertRaises(pp5sim.InputError):
            pp5sim.render("no-such-scenario")

    def test_compare_kernels_reports_every_kernel_with_its_picture(self):
        report = pp5sim.compare_kernels(pp5sim.scenario_from_toml(SMALL))
        names = [row["kernel"] for row in report["kernels"]]
        self.assertEqual(sorted(names), ["levoy", "perm", "wilson", "yuan"])
        for row in report["kernels"]:
            if "refusal" in row:
                self.assertTrue(row["refusal"])
                continue
            self.assertEqual(report["pictures"][row["kernel"]].shape, (32, 32, 4))
            self.assertGreater(row["mean_frame_seconds"], 0.0)
            self.assertEqual(len(row["frame_seconds"]), 2)


if __name__ == "__main__":
    unittest.main()
