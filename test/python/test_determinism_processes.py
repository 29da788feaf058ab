"""The same seeds and actions give the same observations in two processes."""

import hashlib
import subprocess
import sys

EPISODE = """
import hashlib, numpy as np, occlusion_env
env = occlusion_env.make(width=64, height=64)
digest = hashlib.sha256()
observation, info = env.reset(seed=11)
for step in range(5):
    for key in ("rgb", "depth", "pose"):
        digest.update(np.ascontiguousarray(observation[key]).tobytes())
    observation, reward, terminated, truncated, info = env.step([0.6, 0.8])
    digest.update(repr(reward).encode())
observation, info = env.reset()
digest.update(observation["rgb"].tobytes())
print(digest.hexdigest())
"""


def run_in_new_process():
    output = subprocess.run([sys.executable, "-c", EPISODE], check=True, capture_output=True,
                            text=True, timeout=120)
    return output.stdout.strip()


def test_two_processes_agree():
    first, second = run_in_new_process(), run_in_new_process()
    assert len(first) == 64
    assert first == second
