"""`pp5sim serve` end to end: start it on a free loopback port, issue the requests the page's controls
issue (move the light, move the region), check the picture changed and that the page, loaded in headless
Chromium, displays the frame rate the state reports; malformed and oversized requests are refused and
the server keeps serving. The pp5sim binary comes from $PP5SIM."""

import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest
import urllib.error
import urllib.request

SCENARIO = """
[scenario]
name = "serve-test"
[dataset]
phantom = "head"
size = 32
[image]
width = 48
height = 48
[classification]
kind = "piecewise-linear"
points = [{ value = 40.0, opacity = 0.0 }, { value = 120.0, opacity = 0.9 }]
[shading]
specular = 0.0
light_direction = [0.4, 1.0, 0.5]
[region]
shape = "box"
center = [16.0, 10.0, 16.0]
half_size = [6.0, 6.0, 6.0]
scale_inside = 0.0
[[frames]]
label = "first"
"""


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


class ServePageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="pp5_serve_test_")
        scenario = os.path.join(cls.folder, "serve-test.toml")
        with open(scenario, "w") as f:
            f.write(SCENARIO)
        cls.server = subprocess.Popen([os.environ["PP5SIM"], "serve", scenario, "--port", "0"], stdout=subprocess.PIPE, text=True)
        for line in cls.server.stdout:
            match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
            if match:
                cls.base = f"http://127.0.0.1:{match.group(1)}"
                break
        else:
            raise RuntimeError("pp5sim serve did not say where it listens")

    @classmethod
    def tearDownClass(cls):
        cls.server.terminate()
        cls.server.wait(timeout=30)
        shutil.rmtree(cls.folder, ignore_errors=True)

    def get(self, path):
        with urllib.request.urlopen(self.base + path, timeout=60) as r:
            return r.read()

    def post(self, body, content_type="application/json"):
        data = body if isinstance(body, bytes) else json.dumps(body).encode()
        request = urllib.request.Request(self.base + "/api/change", data=data, headers={"Content-Type": content_type})
        try:
            with urllib.request.urlopen(request, timeout=60) as r:
                return r.status, json.loads(r.read())
        except urllib.error.HTTPError as e:
            return e.code, json.loads(e.read())

    def page_dom(self, browser, profile, path="/", budget_ms=10000):
        """The page at `path` as headless Chromium leaves it after `budget_ms` of virtual time."""
        return subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu",
                               "--user-data-dir=" + os.path.join(self.folder, profile),
                               f"--virtual-time-budget={budget_ms}", "--dump-dom", self.base + path],
                              capture_output=True, text=True, timeout=120 + budget_ms // 1000).stdout

    def test_1_the_page_s_changes_render_new_pictures(self):
        first = self.get("/api/image.png")
        status, state = self.post({"light": {"direction": [-0.6, 1.0, 0.3]}})  # a light drag
        self.assertEqual(status, 200, state)
        self.assertTrue(state["frame"]["changed"]["lighting"])
        after_light = self.get("/api/image.png")
        self.assertNotEqual(after_light, first)
        center = state["region"]["center"]
        drag = state["region_drag"]
        moved = [c + 10 * r for c, r in zip(center, drag["right"])]  # a region drag 10 pixels right
        status, state = self.post({"region": {"center": moved}})
        self.assertEqual(status, 200, state)
        self.assertTrue(state["frame"]["changed"]["region"])
        self.assertNotEqual(self.get("/api/image.png"), after_light)

    def test_2_the_page_shows_the_state_s_frame_rate(self):
        browser = chromium()
        if browser is None:
            self.skipTest("no Chromium installed (the setup script installs Debian's chromium)")
        state = json.loads(self.get("/api/state"))
        dom = self.page_dom(browser, "profile")
        match = re.search(r'id="rate"[^>]*data-frames-per-second="([^"]+)"', dom)
        self.assertIsNotNone(match, dom[:2000])
        self.assertAlmostEqual(float(match.group(1)), state["frame"]["frames_per_second"], places=6)
        shown = re.search(r'id="rate"[^>]*>([^<]+)<', dom).group(1)
        self.assertIn(f"{state['frame']['frames_per_second']:.1f} frames/s", shown)
        self.assertIn(f'src="/api/image.png?v={state["version"]}"', dom)
        # The PSNR arrives after the frame, and is the reference's.
        fidelity = json.loads(self.get("/api/fidelity.json"))["fidelity"]
        self.assertIn(f'data-psnr="{fidelity["psnr_db"]}"', dom)
        for kind in ("gps", "renderers", "ring"):
            self.assertIn(f'data-utilisation="{kind}">{100 * state["frame"]["utilisation"][kind]:.0f}%', dom)

    def test_3_bad_requests_are_refused_and_the_server_keeps_serving(self):
        version = json.loads(self.get("/api/state"))["version"]
        self.assertEqual(self.post(b"{not json")[0], 400)
        self.assertEqual(self.post({"camera": {"elevation": 500}})[1]["field"], "camera.elevation")
        self.assertEqual(self.post(b"x" * 200000)[0], 413)
        self.assertEqual(self.post(b"{}", "text/plain")[0], 415)
        with self.assertRaises(urllib.error.HTTPError) as caught:
            self.get("/../../etc/passwd")
        self.assertEqual(caught.exception.code, 404)
        self.assertEqual(json.loads(self.get("/api/state"))["version"], version)

    def test_4_a_machine_change_of_timing_alone_retimes_without_a_new_picture(self):
        before = json.loads(self.get("/api/state"))
        picture = self.get("/api/image.png")
        gps = next(c["value"] for c in before["machine_parameters"] if c["key"] == "gp.count")
        status, state = self.post({"machine": {"gp.count": max(1, gps // 8)}})
        self.assertEqual(status, 200, state)
        self.assertEqual(state["machine_change"]["kind"], "re-timed")
        self.assertLess(state["frame"]["frames_per_second"], before["frame"]["frames_per_second"])  # fewer GPs, slower
        self.assertEqual(self.get("/api/image.png"), picture)
        browser = chromium()
        if browser is not None:
            dom = self.page_dom(browser, "profile-machine")
            self.assertIn(f'data-key="gp.count" value="{max(1, gps // 8)}"', dom)
            self.assertIn("re-timed", dom)
            self.assertIn(f"{state['frame']['frames_per_second']:.1f} frames/s", dom)
        status, state = self.post({"machine": {"renderer.count": 4}})
        self.assertEqual(status, 200, state)
        self.assertEqual(state["machine_change"]["kind"], "rendered again")

    def test_5_the_page_shows_the_passes_in_order_and_where_the_time_went(self):
        state = json.loads(self.get("/api/state"))
        timeline = json.loads(self.get("/api/timeline.json"))
        self.assertEqual(timeline["version"], state["version"])
        self.assertEqual(self.get("/api/tiles.png")[1:4], b"PNG")
        browser = chromium()
        if browser is None:
            self.skipTest("no Chromium installed (the setup script installs Debian's chromium)")
        dom = self.page_dom(browser, "profile-where")
        passes = state["frame"]["passes"]
        self.assertGreater(passes, 1)
        # Each pass was loaded after the one before, and is captioned with the time it was ready.
        shown = [int(p) for p in re.findall(r'data-pass="(\d+)"', dom)]
        self.assertEqual(shown, list(range(passes)))
        for p, seconds in enumerate(state["frame"]["passes_ready_seconds"]):
            self.assertIn(f"pass {p + 1} of {passes} · {1000 * seconds:.1f} ms", dom)
        self.assertIn(f'data-lanes="{len(timeline["lanes"])}"', dom)
        used = {timeline["activities"][w] for lane in timeline["lanes"] for w in lane["what"] if w >= 0}
        legend = re.search(r'<div id="timeline-legend">(.*?)</div>', dom, re.S)
        self.assertIsNotNone(legend, dom[:2000])
        self.assertEqual(set(re.findall(r'data-activity="([^"]+)"', legend.group(1))), used)
        self.assertIn(f'src="/api/tiles.png?v={state["version"]}"', dom)

    def test_6_the_page_compares_every_kernel_on_the_view(self):
        request = urllib.request.Request(self.base + "/api/compare", data=b"", method="POST")
        with urllib.request.urlopen(request, timeout=120) as r:
            report = json.loads(r.read())
        rendered = [k["kernel"] for k in report["kernels"] if "refusal" not in k]
        self.assertIn("levoy", rendered)
        self.assertEqual(self.get(f"/api/compare/{rendered[0]}.png")[1:4], b"PNG")
        browser = chromium()
        if browser is None:
            self.skipTest("no Chromium installed (the setup script installs Debian's chromium)")
        dom = self.page_dom(browser, "profile-compare", "/#compare", 60000)
        # A row for every kernel on the machine, and a picture for each that rendered the view.
        table = re.search(r'<table id="comparison-table">(.*?)</table>', dom, re.S)
        self.assertIsNotNone(table, dom[:2000])
        self.assertEqual(re.findall(r'<tr data-kernel="([^"]+)"', table.group(1)), [k["kernel"] for k in report["kernels"]])
        for kernel in rendered:
            self.assertIn(f'src="/api/compare/{kernel}.png?v=', dom)


if __name__ == "__main__":
    unittest.main()
