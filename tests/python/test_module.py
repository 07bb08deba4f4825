"""The Python module against the command line (ctest `python`, label scene).

Run by ctest with PYTHONPATH at the build's python/ folder and STERADIAN_EXE the command-line
binary of the same build. The module and the command line share the library, so the same scene,
seed and sample count must give the same numbers bit for bit: the image the CLI writes as PFM
(32-bit floats), the meters' JSON.
"""
import json
import os
import pathlib
import subprocess
import signal
import sys
import threading
import time

import numpy as np
import pytest

import steradian

EXE = os.environ.get("STERADIAN_EXE", "steradian")
SOURCE = pathlib.Path(os.environ.get("STERADIAN_SOURCE_DIR", pathlib.Path(__file__).parents[2]))

SCENE = """
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ 8 ]
Integrator "path" "integer maxdepth" [ 4 ]
WorldBegin
LightSource "point" "point3 from" [ 1 3 -1 ] "rgb I" [ 4 4 4 ]
LightSource "infinite" "rgb L" [ 0.1 0.12 0.15 ]
Material "diffuse" "rgb reflectance" [ 0.7 0.5 0.3 ]
Shape "sphere" "float radius" [ 0.5 ]
Material "conductor" "float roughness" [ 0.1 ]
Shape "bilinearmesh" "point3 P" [ -3 0 -3  3 0 -3  -3 0 3  3 0 3 ]
"""

METERS = """
Meter "illuminance" "string name" "desk" "point3 p" [ 0.5 0.01 0.2 ] "normal n" [ 0 1 0 ]
Meter "illuminancegrid" "string name" "floor" "point3 corner" [ -2 0.01 -2 ]
    "vector3 u" [ 4 0 0 ] "vector3 v" [ 0 0 4 ] "integer resolution" [ 3 2 ]
"""


def read_pfm(path):
    """A PFM file as an H x W x 3 float32 array, top row first (PFM stores bottom-up)."""
    data = pathlib.Path(path).read_bytes()
    header, rest = [], data
    while len(header) < 3:
        line, rest = rest.split(b"\n", 1)
        header.append(line.strip())
    assert header[0] == b"PF"
    w, h = (int(v) for v in header[1].split())
    scale = float(header[2])
    a = np.frombuffer(rest, dtype="<f4" if scale < 0 else ">f4", count=w * h * 3)
    return a.reshape(h, w, 3)[::-1].astype(np.float32)


def cli(*args, cwd):
    subprocess.run([EXE, *args], cwd=cwd, check=True, capture_output=True)


def test_render_equals_the_command_lines_image_bit_for_bit(tmp_path):
    (tmp_path / "s.pbrt").write_text(SCENE)
    cli("render", "s.pbrt", "-q", "--spp", "8", "--seed", "3", "-o", "x.pfm", cwd=tmp_path)
    expected = read_pfm(tmp_path / "x.pfm")
    scene = steradian.load(str(tmp_path / "s.pbrt"))
    assert scene.resolution == (24, 16)
    img = scene.render(spp=8, seed=3, threads=1)
    assert img.dtype == np.float32 and img.shape == (16, 24, 3)
    assert np.array_equal(img, expected)
    assert img.max() > 0
    # Any number of threads gives the same image (the project's determinism rule).
    assert np.array_equal(scene.render(spp=8, seed=3, threads=2), img)
    # loads() with the same text: the same scene.
    assert np.array_equal(steradian.loads(SCENE).render(spp=8, seed=3), img)
    # Another seed: another image.
    assert not np.array_equal(scene.render(spp=8, seed=4), img)


def test_a_scene_error_raises_with_its_location(tmp_path):
    bad = SCENE.replace('"float radius" [ 0.5 ]', '"float radius" [ 0.5 ] "float radios" [ 1 ]')
    (tmp_path / "bad.pbrt").write_text(bad)
    with pytest.raises(steradian.Error) as info:
        steradian.load(str(tmp_path / "bad.pbrt"))
    e = info.value
    line = next(i for i, l in enumerate(bad.split("\n"), 1) if "radios" in l)
    assert e.file == str(tmp_path / "bad.pbrt")
    assert e.line == line
    assert e.column == bad.split("\n")[line - 1].index('"float radios"') + 1
    assert "radios" in e.message
    assert isinstance(e, RuntimeError)
    with pytest.raises(steradian.Error) as info:
        steradian.loads("WorldBegin\nShape \"sphere\" \"float radius\" [ -1 ", name="t.pbrt")
    assert info.value.file == "t.pbrt" and info.value.line == 2


def test_measure_matches_the_command_lines_json(tmp_path):
    (tmp_path / "m.pbrt").write_text(SCENE + METERS)
    cli("measure", "m.pbrt", "-q", "--rel-error", "0.02", "--threads", "2", "--json", "m.json",
        cwd=tmp_path)
    expected = json.loads((tmp_path / "m.json").read_text())
    r = steradian.load(str(tmp_path / "m.pbrt")).measure(rel_error=0.02, threads=2)
    assert [m["name"] for m in r["meters"]] == ["desk", "floor"]
    for got, want in zip(r["meters"], expected["meters"]):
        assert isinstance(got["values"], np.ndarray)
        assert got["values"].tolist() == want["values"]
        assert got["stderr"].tolist() == want["stderr"]
        assert got["unit"] == want["unit"]
    floor = r["meters"][1]
    assert floor["grid"].shape == (2, 3)  # nv x nu, row by row along u
    assert floor["grid"][1, 0] == floor["values"][3]
    assert floor["grid_stderr"].shape == (2, 3)


def test_auxiliary_channels_of_a_gbuffer_film():
    text = SCENE.replace('Film "rgb"', 'Film "gbuffer"')
    scene = steradian.loads(text)
    out = scene.render(spp=4, aov=["Albedo", "N", "u"])
    assert set(out) == {"rgb", "Albedo", "N", "u"}
    assert out["Albedo"].shape == (16, 24, 3) and out["u"].shape == (16, 24)
    # Normals are unit vectors where a surface is seen (a pixel's mean of them: at most 1).
    n = np.linalg.norm(out["N"], axis=2)
    assert n.max() <= 1 + 1e-5 and n.max() > 0.99
    everything = scene.render(spp=4, aov=True)
    assert {"Albedo", "P", "N", "Ns", "u", "v"} <= set(everything)
    with pytest.raises(ValueError, match="Albedo"):
        steradian.loads(SCENE).render(spp=1, aov=["Albedo"])


def test_progress_callback_and_interruption():
    scene = steradian.loads(SCENE)
    seen = []
    scene.render(spp=64, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (64, 64)
    assert all(b >= a for (a, _), (b, _) in zip(seen, seen[1:]))

    # An exception in the callback stops the render at its next pass and propagates (as
    # Ctrl-C's KeyboardInterrupt does through the same path).
    def stop(done, total):
        raise KeyboardInterrupt

    big = steradian.loads(SCENE.replace("[ 24 ]", "[ 240 ]").replace("[ 16 ]", "[ 160 ]"))
    with pytest.raises(KeyboardInterrupt):
        big.render(spp=1024, progress=stop)


def test_the_gil_is_released_while_rendering():
    scene = steradian.loads(SCENE.replace("[ 24 ]", "[ 96 ]").replace("[ 16 ]", "[ 64 ]"))
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    t = threading.Thread(target=count)
    t.start()
    scene.render(spp=256, threads=2)
    done.set()
    t.join()
    assert len(ticks) > 5  # the other thread ran during the render


def test_bundled_cornell_box_loads_and_renders():
    scene = steradian.load(str(SOURCE / "scenes" / "cornell-box.pbrt"))
    img = scene.render(spp=1, time=0)
    assert img.shape[2] == 3 and np.isfinite(img).all() and img.mean() > 0


def test_ctrl_c_stops_the_render_with_keyboard_interrupt(tmp_path):
    # A child process renders for a long time; SIGINT must end it with KeyboardInterrupt
    # within a few of the module's quarter-second passes, not after the whole render.
    child = tmp_path / "child.py"
    child.write_text(
        "import signal, sys, time, steradian\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        f"s = steradian.load({str(SOURCE / 'scenes' / 'cornell-box.pbrt')!r})\n"
        "print('rendering', flush=True)\n"
        "t = time.time()\n"
        "try:\n"
        "    s.render(spp=65536, threads=1)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted %.2f' % (time.time() - t), flush=True)\n"
        "    sys.exit(3)\n")
    p = subprocess.Popen([sys.executable, str(child)], stdout=subprocess.PIPE, text=True,
                         env=dict(os.environ))
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    assert p.returncode == 3, out
    assert out.startswith("interrupted")
