"""Levoy's adaptive refinement, pass by pass: render one frame on the simulated machine and show each
pass's picture side by side with the simulated time at which it was complete.

    PYTHONPATH=build/python python3 examples/refinement_passes.py [--scenario mr-head] [--out out/examples]
"""

import argparse
import os

import matplotlib.pyplot as plt
import numpy as np
import pp5sim

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scenario", default="mr-head")
parser.add_argument("--out", default="out/examples")
args = parser.parse_args()

scenario = pp5sim.load_scenario(args.scenario)
frame = pp5sim.render(scenario, frames=1).frames[0]
passes = frame.passes
times = [p["complete_seconds"] for p in frame.record.get("machine", {}).get("passes", [])]

os.makedirs(args.out, exist_ok=True)
fig, axes = plt.subplots(1, len(passes), figsize=(3.2 * len(passes), 3.6), squeeze=False)
for i, (ax, image) in enumerate(zip(axes[0], passes)):
    ax.imshow(np.clip(image[..., :3], 0.0, 1.0))
    ax.set_axis_off()
    when = f", done at {times[i] * 1000:.0f} ms" if i < len(times) else ""
    ax.set_title(f"pass {i}{when}", fontsize=10)
    print(f"pass {i}{when}")
fig.suptitle(f"{scenario.name}: adaptive refinement on the simulated machine ({frame.simulated_seconds * 1000:.0f} ms in all)")
path = os.path.join(args.out, "refinement_passes.png")
fig.savefig(path, dpi=110, bbox_inches="tight")
print("wrote", path)
