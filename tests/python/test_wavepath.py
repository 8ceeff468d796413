# The module against the command line: the same images, merges and
# messages (the spectral mode's too); Ctrl-C, the arrays' lifetime, renders
# in two threads, and the SIMT model's rows.
import gc
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import wavepath
from conftest import CORNELL, DATA, cli


def test_render_equals_the_command_lines_exr(small, gpu_render, tmp_path):
    # The default device and the CPU reference, each against `wavepath
    # render` at the same seed and samples: equal to float rounding (the EXR
    # holds float32 means of the same double sums). A render of another seed
    # differs, so the comparison can fail.
    cpu = wavepath.render(small, device="cpu", seed=3)
    for r, flags in ((gpu_render, []), (cpu, ["--cpu"])):
        out = tmp_path / ("cli-cpu.exr" if flags else "cli.exr")
        status, err = cli("render", CORNELL, "-r", 32, 32, "--spp", 4, "--seed", 3, "-o", out, "-q", *flags)
        assert status == 0, err
        exr = wavepath.read(out)
        assert r.mean.shape == (32, 32, 3) and r.mean.dtype == np.float32
        assert r.mean.mean() > 0.01
        np.testing.assert_array_equal(r.count, exr.count)
        np.testing.assert_allclose(r.mean, exr.mean, rtol=2**-23, atol=0)
        np.testing.assert_allclose(r.variance, exr.variance, rtol=2**-23, atol=0)
        assert r.settings == exr.settings and r.scene_hash == exr.scene_hash
        assert not r.partial and r.samples == [(0, 4)]
    other = wavepath.render(small, device="cpu", seed=4)
    assert not np.allclose(other.mean, cpu.mean, rtol=1e-3)


def test_a_spectral_render_equals_the_command_lines(tmp_path):
    # spectral=True is --spectral: the CPU reference's image at the same seed
    # equals the command line's to float rounding, its settings say so, and
    # it is not the RGB render's image.
    scene = wavepath.load(CORNELL, resolution=(24, 24), spp=4, spectral=True)
    r = wavepath.render(scene, device="cpu", seed=3)
    out = tmp_path / "spectral.exr"
    status, err = cli("render", CORNELL, "-r", 24, 24, "--spp", 4, "--seed", 3, "--spectral", "--cpu", "-o", out, "-q")
    assert status == 0, err
    exr = wavepath.read(out)
    np.testing.assert_allclose(r.mean, exr.mean, rtol=2**-23, atol=0)
    assert "colour=spectral" in r.settings and r.settings == exr.settings
    rgb = wavepath.render(wavepath.load(CORNELL, resolution=(24, 24), spp=4), device="cpu", seed=3)
    assert "colour=spectral" not in rgb.settings
    assert not np.allclose(rgb.mean, r.mean, rtol=1e-3)


def test_merge_of_two_sample_ranges_equals_the_whole_render(small, tmp_path):
    # On the CPU reference, whose documented bound for a split render is
    # 1e-12 of the sums (docs/partial-renders.md); one sample fewer is far outside it.
    whole = wavepath.render(small, device="cpu", seed=3)
    first = wavepath.render(small, device="cpu", seed=3, samples=(0, 1))
    rest = wavepath.render(small, device="cpu", seed=3, samples="1:4")
    assert first.partial and rest.samples == [(1, 4)]
    # A file part merges with an in-memory one, as `wavepath merge` merges files.
    rest.save(tmp_path / "rest.exr")
    merged = wavepath.merge([first, tmp_path / "rest.exr"])
    assert not merged.partial and merged.samples == [(0, 4)] and merged.status == "complete"
    np.testing.assert_array_equal(merged.count, whole.count)
    np.testing.assert_allclose(merged.sum, whole.sum, rtol=1e-12, atol=1e-12)
    assert not np.allclose(rest.sum, whole.sum, rtol=1e-3)
    # Its refusals are the command's: an overlap, and the missing samples.
    with pytest.raises(ValueError, match="overlaps"):
        wavepath.merge([first, first])
    with pytest.raises(ValueError, match="1:4"):
        wavepath.merge([first])


def test_a_wrong_key_gives_the_command_lines_message(small, tmp_path):
    bad = DATA / "bad-unknown-key.json"
    status, err = cli("render", bad, "-o", tmp_path / "x.png")
    assert status == 2
    assert err.startswith("wavepath: error: ")
    with pytest.raises(ValueError) as e:
        wavepath.load(bad)
    assert str(e.value) == err[len("wavepath: error: "):].strip()
    assert 'unknown key "fov"' in str(e.value)
    # A missing file, a bad override and an unknown one, each as Python says them.
    with pytest.raises(FileNotFoundError):
        wavepath.load(DATA / "no-such-scene.json")
    with pytest.raises(ValueError, match="--spp"):
        wavepath.load(CORNELL, spp=0)
    with pytest.raises(TypeError, match="spp"):
        wavepath.load(CORNELL, spps=4)
    with pytest.raises(ValueError, match="unknown integrator"):
        small.integrator = "path tracer typo"
    assert small.integrator == "path tracer mis"


def test_keyboard_interrupt_returns_a_partial_render(tmp_path):
    # Ctrl-C as a terminal or Jupyter sends it: SIGINT to the process while
    # it renders. The render stops at the end of its pass and returns the
    # samples done. Without a progress callback the render sees it through
    # PyErr_CheckSignals (here a second in, long after the first pass of a
    # 16x16 image on the CPU); with one, Python raises it in the callback.
    # A budget ends the render if the interrupt is missed: the status then says so.
    scene = wavepath.load(CORNELL, resolution=(16, 16))
    scene.spp = 1 << 24
    first_pass = threading.Event()

    def interrupt(after):
        after()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt, args=(lambda: time.sleep(1.0),), daemon=True).start()
    r = wavepath.render(scene, device="cpu", time=60)
    threading.Thread(target=interrupt, args=(lambda: first_pass.wait(60),), daemon=True).start()
    called = wavepath.render(scene, device="cpu", time=60, progress=lambda fraction: first_pass.set())
    for x in (r, called):
        assert x.partial and x.status == "interrupted by KeyboardInterrupt"
        (begin, end), = x.samples
        assert begin == 0 and 0 < end < 1 << 24
        assert (x.count == end).all()
    # Saved, it is the partial file `wavepath render` leaves when interrupted.
    r.save(tmp_path / "partial.exr")
    again = wavepath.read(tmp_path / "partial.exr")
    assert again.partial and again.status == r.status and again.samples == r.samples


def test_the_arrays_outlive_the_render():
    r = wavepath.render(wavepath.load(CORNELL, resolution=(16, 16), spp=2), device="cpu", aov=("albedo", "depth"))
    arrays = {"mean": r.mean, "variance": r.variance, "count": r.count, "sum": r.sum,
              "albedo": r.aov["albedo"], "depth": r.aov["depth"]}
    copies = {k: np.array(v, copy=True) for k, v in arrays.items()}
    # count and the sums view the render's own buffers (no copy); the
    # means are made once and kept.
    assert np.shares_memory(r.count, r.count) and np.shares_memory(r.sum, r.sum)
    assert r.mean is r.mean
    with pytest.raises(ValueError):
        arrays["mean"][0, 0, 0] = 1.0
    del r
    gc.collect()
    clutter = [np.full((64, 64, 3), 7.0) for _ in range(64)]  # reuses freed memory, if the arrays had let it go
    for k, v in arrays.items():
        np.testing.assert_array_equal(v, copies[k], err_msg=k)
    assert arrays["depth"].shape == (16, 16, 2) and arrays["sum"].shape[2] == 4 + 3 + 2
    del clutter


def test_two_threads_render_at_once(small, gpu_render):
    # Each thread renders on its own Vulkan context with the GIL released:
    # both images are the one rendered alone, and the main thread runs
    # while they render.
    results, errors = [None, None], []

    def work(i):
        try:
            results[i] = wavepath.render(small, seed=3)
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    ticks = 0
    while any(t.is_alive() for t in threads):
        ticks += 1
        time.sleep(0.001)
    assert not errors, errors
    for r in results:
        np.testing.assert_array_equal(r.sum, gpu_render.sum)
    # Two renders of well over 0.1 s each: a render holding the GIL would
    # have left the loop a few turns at most.
    assert ticks > 50


def test_bench_simt_rows_are_the_command_lines(tmp_path):
    # The SIMT model (bench --simt) is deterministic: the rows equal its
    # --out JSON's, one per ray set, variant and warp width.
    status, err = cli("bench", "--simt", "--scenes", CORNELL, "--resolution", 16, 16, "--out", tmp_path / "simt.json")
    assert status == 0, err
    rows = wavepath.bench(CORNELL, mode="simt", resolution=(16, 16))
    assert rows == json.load(open(tmp_path / "simt.json"))["simt"]
    assert {r["warp_width"] for r in rows} == {32, 64} and {r["rays_set"] for r in rows} == {"primary", "bounce", "shadow"}
    assert len({r["variant"] for r in rows}) > 1
    with pytest.raises(ValueError, match="simt"):
        wavepath.bench(mode="simd")
