"""The PPO example (examples/ppo_vector_env.py) runs two tiny updates end to end."""

import os
import re
import subprocess
import sys

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "ppo_vector_env.py")


def test_ppo_example_two_updates(tmp_path):
    saved = tmp_path / "policy.pt"
    output = subprocess.run(
        [sys.executable, EXAMPLE, "--updates", "2", "--num-envs", "2", "--num-steps", "16",
         "--max-steps", "6", "--update-epochs", "1", "--save", str(saved)],
        check=True, capture_output=True, text=True, timeout=600).stdout
    lines = [line for line in output.splitlines() if line.startswith("update ")]
    assert [line.split()[1] for line in lines] == ["1/2", "2/2"]
    for line in lines:
        losses = re.findall(r"loss (\S+)", line)
        assert len(losses) == 2 and all(abs(float(value)) < 1e6 for value in losses), line
    episodes = int(re.search(r"episodes (\d+)", lines[-1]).group(1))
    assert episodes >= 2 * (32 // 7)  # per env: an episode of <= 6 steps + 1 reset step
    assert saved.stat().st_size > 0
