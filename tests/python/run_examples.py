"""Runs the lecture examples as a user would (on the small head phantom, to stay quick) and checks each
wrote its picture: a PNG that matplotlib can read back, not blank."""

import os
import subprocess
import sys
import tempfile

import matplotlib.image

examples = sys.argv[1]
with tempfile.TemporaryDirectory(prefix="pp5_examples_") as out:
    for script, picture in (("gp_sweep.py", "gp_sweep.png"), ("refinement_passes.py", "refinement_passes.png")):
        subprocess.run([sys.executable, os.path.join(examples, script), "--scenario", "head-phantom", "--out", out], check=True)
        image = matplotlib.image.imread(os.path.join(out, picture))
        assert image.shape[0] > 100 and image.shape[1] > 100, (picture, image.shape)
        assert image.std() > 0.01, picture + " is blank"
print("examples ran and wrote their pictures")
