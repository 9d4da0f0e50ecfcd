"""How Levoy's frame time falls with the number of GPs: record the scenario's work once, then time it on
machines with 4 to 128 GPs (no re-rendering: the recording is re-timed), and plot the crude and fully
refined times. A lecture's first experiment: where does adding processors stop paying?

By default the frame is mr-head-sequence's "observer moved": the PPs have already shaded and the
pyramid is built, so the frame is the GPs' ray casting alone (frame 0 would add the pyramid's build,
which no GP count shortens).

    PYTHONPATH=build/python python3 examples/gp_sweep.py [--scenario mr-head-sequence] [--frame 1] [--out out/examples]
"""

import argparse
import os

import matplotlib.pyplot as plt
import pp5sim

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scenario", default="mr-head-sequence")
parser.add_argument("--frame", type=int, default=1, help="which frame of the scenario (the last, if it has fewer)")
parser.add_argument("--out", default="out/examples")
args = parser.parse_args()

scenario = pp5sim.load_scenario(args.scenario)
recording = pp5sim.record(scenario)  # renders once, on the stock 32-GP machine
gp_counts = [4, 8, 16, 32, 64, 128]
crude, refined = [], []
print(f"{'GPs':>5} {'crude s':>10} {'refined s':>10} {'frames/s':>9}")
for gps in gp_counts:
    frames = recording.time_on(pp5sim.Machine("pxpl5", {"gp.count": gps}))
    frame = frames[min(args.frame, len(frames) - 1)]
    crude.append(frame.metrics.get("crude_seconds", frame.simulated_seconds))
    refined.append(frame.simulated_seconds)
    print(f"{gps:>5} {crude[-1]:>10.4f} {refined[-1]:>10.4f} {1 / refined[-1]:>9.2f}")

os.makedirs(args.out, exist_ok=True)
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(gp_counts, crude, "o-", label="crude (first pass)")
ax.plot(gp_counts, refined, "s-", label="fully refined")
ax.plot(gp_counts, [refined[0] * gp_counts[0] / g for g in gp_counts], ":", color="gray", label="perfect scaling")
ax.set_xscale("log", base=2)
ax.set_yscale("log")
ax.set_xlabel("graphics processors")
ax.set_ylabel("simulated seconds per frame")
ax.set_title(f"{scenario.name}, frame '{frame.label}', on Pixel-planes 5 ({scenario.kernel} kernel)")
ax.legend()
ax.grid(True, which="both", alpha=0.3)
path = os.path.join(args.out, "gp_sweep.png")
fig.savefig(path, dpi=120, bbox_inches="tight")
print("wrote", path)
