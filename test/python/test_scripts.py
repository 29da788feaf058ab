"""Scripts that read the tools' output: scripts/rollout_progress.py on a DAgger set made here."""
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROLLOUT_PROGRESS = os.path.join(ROOT, "scripts", "rollout_progress.py")


def write_rollout(dataset, scene, oracle_steps):
    folder = dataset / "train" / f"{scene:06d}"
    folder.mkdir(parents=True)
    labels = {str(i): {"oracle_steps": s, "occlusion_px": 0} for i, s in enumerate(oracle_steps)}
    (folder / "scene_labels.json").write_text(json.dumps(labels))


def run(*args):
    return subprocess.run([sys.executable, ROLLOUT_PROGRESS, *map(str, args)],
                          capture_output=True, text=True)


def test_moves_are_classed_by_the_oracles_count_before_them(tmp_path):
    # Roll-out 0: 3 -> 2 (progress), 2 -> 2 (none), 2 -> 1 (progress), 1 -> 0 (progress).
    # Roll-out 1: 3 -> 4 (regress), 4 -> 1 (jump), 1 -> 0 (progress).
    # Roll-out 2 ends occluded (the step limit) and is left out.
    write_rollout(tmp_path, 0, [3, 2, 2, 1, 0])
    write_rollout(tmp_path, 1, [3, 4, 1, 0])
    write_rollout(tmp_path, 2, [5, 5])
    result = run(tmp_path)
    assert result.returncode == 0, result.stderr
    assert "2 roll-outs that reached an unoccluded view (1 did not)" in result.stdout
    # 7 moves over 2 roll-outs against 3 + 3 oracle steps.
    assert "3.50 moves against the oracle's 3.00 steps" in result.stdout
    assert "(1.167x)" in result.stdout
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in result.stdout.splitlines() if line.startswith("| ") and "%" in line}
    assert rows["1"] == ["1.00", "100 %", "0 %", "0 %", "0 %"]
    assert rows["2"] == ["1.00", "50 %", "50 %", "0 %", "0 %"]
    assert rows["3"] == ["1.00", "50 %", "0 %", "50 %", "0 %"]
    assert rows["4"] == ["0.50", "0 %", "0 %", "0 %", "100 %"]


def test_a_set_without_finished_rollouts_is_refused(tmp_path):
    write_rollout(tmp_path, 0, [2, 2])
    result = run(tmp_path)
    assert result.returncode != 0
    assert "no finished roll-out" in result.stderr


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))
