#!/usr/bin/python3
"""Host time of a simulated frame against VTK rendering the same voxels on the same host.

The MR head ch2 resampled to 256^3 (trilinear), 512x512 pixels, the observer turning 5 degrees a
frame. pp5sim runs Levoy's kernel on the default Pixel-planes 5 (32 GPs), every pixel cast (no
adaptive refinement), without the host reference: once with a light fixed to the head (frames after
the first only ray-cast) and once with a headlight (the PPs reshade every frame). VTK 9.1's CPU
fixed-point ray caster renders the same resampled volume with diffuse shading and an opacity ramp
over the same isovalue, under Xvfb. Reported: wall milliseconds per frame, medians over the orbit frames.

Needs python3-vtk9, xvfb and mricron-data (Debian). Usage:
    xvfb-run -a /usr/bin/python3 tests/benchmarks/vs_vtk.py build/frontends/pp5sim [--threads N]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

CH2 = "/usr/share/mricron/templates/ch2.nii.gz"
SIZE = 256
IMAGE = 512
FRAMES = 6  # the first classifies and shades; the other five are timed
STEP_DEGREES = 5.0

SCENARIO = """
[scenario]
name = "vs-vtk-{light}"
description = "ch2 at 256^3, orbit, for the VTK comparison"
kernel = "levoy"

[dataset]
packaged = "ch2"
resample = [{size}, {size}, {size}]

[classification]
kind = "isovalue-contours"
contours = [{{ value = 40.0, opacity = 0.95, thickness = 1.5 }}]
colors = [{{ value = 0.0, color = [0.95, 0.78, 0.66] }}, {{ value = 255.0, color = [1.0, 0.9, 0.82] }}]

[shading]
ambient = 0.15
diffuse = 0.75
{light_lines}

[camera]
projection = "parallel"
view_from = [0.0, 1.0, 0.0]
up = [0.0, 0.0, 1.0]
azimuth = 30.0
elevation = 10.0
zoom = 1.15

[image]
width = {image}
height = {image}
"""


def pp5sim_frames(binary, light, threads, workdir):
    # A light fixed to the head without a highlight leaves every voxel's colour alone as the observer
    # turns; a headlight with a highlight makes the PPs reshade every frame.
    if light == "headlight":
        light_lines = 'specular = 0.25\nshininess = 16.0\nlight = "headlight"'
    else:
        light_lines = "specular = 0.0\nlight_direction = [0.4, 1.0, 0.5]"
    text = SCENARIO.format(light=light, size=SIZE, image=IMAGE, light_lines=light_lines)
    for f in range(FRAMES):
        text += '\n[[frames]]\nlabel = "frame {0}"\ncamera = {{ azimuth = {1} }}\n'.format(f, 30.0 + STEP_DEGREES * f)
    scenario = os.path.join(workdir, "vs-vtk-" + light + ".toml")
    with open(scenario, "w") as out:
        out.write(text)
    run_dir = os.path.join(workdir, "run-" + light)
    command = [binary, "render", scenario, "--no-reference", "--out", run_dir, "--threads", str(threads),
               "--set", "levoy.refinement_threshold=-1"]
    started = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    whole = time.perf_counter() - started
    with open(os.path.join(run_dir, "stats.json")) as f:
        stats = json.load(f)
    frames = [frame["host_seconds"] for frame in stats["frames"]]
    return frames, whole


def vtk_frames(threads):
    import vtk
    vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(threads)
    started = time.perf_counter()
    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(CH2)
    reader.Update()
    extent = reader.GetOutput().GetDimensions()
    resample = vtk.vtkImageResample()
    resample.SetInputConnection(reader.GetOutputPort())
    resample.SetInterpolationModeToLinear()
    for axis in range(3):
        resample.SetAxisMagnificationFactor(axis, (SIZE - 1) / (extent[axis] - 1))
    resample.Update()

    opacity = vtk.vtkPiecewiseFunction()
    opacity.AddPoint(20, 0.0)
    opacity.AddPoint(60, 0.95)
    color = vtk.vtkColorTransferFunction()
    color.AddRGBPoint(0, 0.95, 0.78, 0.66)
    color.AddRGBPoint(255, 1.0, 0.9, 0.82)
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(color)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    prop.SetAmbient(0.15)
    prop.SetDiffuse(0.75)
    prop.SetSpecular(0.0)
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputConnection(resample.GetOutputPort())
    mapper.SetNumberOfThreads(threads)
    mapper.SetAutoAdjustSampleDistances(0)
    mapper.SetSampleDistance(1.0)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    renderer = vtk.vtkRenderer()
    renderer.AddVolume(volume)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(IMAGE, IMAGE)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.ParallelProjectionOn()
    renderer.ResetCamera()
    camera.Azimuth(30.0)
    camera.Elevation(10.0)
    frames = []
    for f in range(FRAMES):
        t = time.perf_counter()
        window.Render()
        frames.append(time.perf_counter() - t)
        camera.Azimuth(STEP_DEGREES)
    return frames, time.perf_counter() - started


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("pp5sim")
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    args = parser.parse_args()
    if not os.path.exists(CH2):
        sys.exit("needs the ch2 volume: apt-get install mricron-data")
    ms = lambda seconds: 1e3 * seconds
    with tempfile.TemporaryDirectory() as workdir:
        fixed, fixed_whole = pp5sim_frames(args.pp5sim, "fixed", args.threads, workdir)
        head, head_whole = pp5sim_frames(args.pp5sim, "headlight", args.threads, workdir)
    vtk_times, vtk_whole = vtk_frames(args.threads)
    vtk_orbit = statistics.median(vtk_times[1:])
    rows = [
        ("VTK 9.1 fixed-point ray caster", vtk_orbit, vtk_times[0], vtk_whole),
        ("pp5sim, fixed light (ray casting only)", statistics.median(fixed[1:]), fixed[0], fixed_whole),
        ("pp5sim, headlight (PPs reshade each frame)", statistics.median(head[1:]), head[0], head_whole),
    ]
    print(f"ch2 at {SIZE}^3, {IMAGE}x{IMAGE}, {args.threads} threads; medians of {FRAMES - 1} orbit frames")
    print(f"{'':44} {'frame ms':>9} {'x VTK':>6} {'first ms':>9} {'process s':>10}")
    for name, orbit, first, whole in rows:
        print(f"{name:44} {ms(orbit):9.1f} {orbit / vtk_orbit:6.2f} {ms(first):9.1f} {whole:10.2f}")


if __name__ == "__main__":
    main()
