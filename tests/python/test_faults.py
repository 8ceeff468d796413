# The faults of docs/partial-renders.md ("Faults") from Python: a lost
# device raises DeviceLost carrying the samples of the passes that ended,
# which merge with a render of the rest into the whole render; a write that
# fails raises OSError and leaves no file. WAVEPATH_FAULT is read once a
# process, so each case runs in an interpreter of its own.
import json
import os
import subprocess
import sys
import textwrap

import wavepath
from conftest import CORNELL


def run_with_fault(fault, code):
    """Runs `code` under WAVEPATH_FAULT=fault in a new interpreter; returns what it prints as JSON."""
    env = dict(os.environ, WAVEPATH_FAULT=fault)
    module_dir = os.path.dirname(wavepath.__file__)
    prelude = f"import json, sys; sys.path.insert(0, {module_dir!r}); import numpy as np, wavepath\nCORNELL = {CORNELL!r}\n"
    p = subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)], env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_a_lost_device_raises_with_the_samples_kept(tmp_path):
    # The 3rd submission of samples is lost: the passes before it are kept
    # (samples 0:k), the message says how to finish, and the kept part and a
    # render of k:16 merge into the whole render's sums (a render of k:16
    # alone is far from them, so the check can fail). Saving it first hits
    # the injected full disk (the 1st file written): OSError, no file.
    out = run_with_fault("device-lost@submit:3,enospc@write:1", f"""
        scene = wavepath.load(CORNELL, resolution=(32, 32), spp=16)
        try:
            wavepath.render(scene, seed=3)
            raise SystemExit("no DeviceLost")
        except wavepath.DeviceLost as e:
            lost = e
        assert isinstance(lost, RuntimeError)
        kept = lost.render
        (begin, k), = kept.samples
        try:
            kept.save({str(tmp_path / "full.exr")!r})
            raise SystemExit("no OSError")
        except OSError as e:
            full = str(e)
        kept.save({str(tmp_path / "kept.exr")!r})
        rest = wavepath.render(scene, seed=3, samples=(k, 16))
        whole = wavepath.render(scene, seed=3)
        merged = wavepath.merge([{str(tmp_path / "kept.exr")!r}, rest])
        print(json.dumps(dict(
            message=str(lost), begin=begin, k=k, partial=kept.partial, status=kept.status, full=full,
            merged=merged.samples, merged_status=merged.status,
            counts_equal=bool((merged.count == whole.count).all()),
            sums_close=bool(np.allclose(merged.sum, whole.sum, rtol=1e-5, atol=1e-9)),
            rest_close=bool(np.allclose(rest.sum, whole.sum, rtol=1e-3)))))
    """)
    k = out["k"]
    assert out["begin"] == 0 and 0 < k < 16, out
    assert out["partial"] and out["status"].startswith("device lost: "), out
    assert out["message"].startswith("device lost: ") and f"kept samples 0:{k} (of 0:16)" in out["message"], out
    assert f"a render of samples=({k}, 16)" in out["message"], out
    assert "full.exr: cannot write EXR: No space left on device" in out["full"], out
    assert not (tmp_path / "full.exr").exists()
    assert out["merged"] == [[0, 16]] and out["merged_status"] == "complete", out
    assert out["counts_equal"] and out["sums_close"] and not out["rest_close"], out


def test_a_device_lost_before_a_pass_keeps_nothing():
    out = run_with_fault("device-lost@submit:1", """
        try:
            wavepath.render(wavepath.load(CORNELL, resolution=(16, 16), spp=2))
            raise SystemExit("no DeviceLost")
        except wavepath.DeviceLost as e:
            print(json.dumps(dict(message=str(e), render=e.render is None)))
    """)
    assert out["render"] and "before a single pass was done: no samples kept" in out["message"], out
