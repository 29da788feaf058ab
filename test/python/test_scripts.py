"""Scripts that read the tools' output: scripts/rollout_progress.py on a DAgger set made here,
scripts/paired_steps.py on episode CSVs written here (steps, pairs, turning back, spread),
scripts/robustness.py on bridge summaries, scripts/stopping_rules.py on calibration views written
here, scripts/depth_coverage.py on frames and scripts/plot_iou_by_radius.py on check files written
here."""
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROLLOUT_PROGRESS = os.path.join(ROOT, "scripts", "rollout_progress.py")
PAIRED_STEPS = os.path.join(ROOT, "scripts", "paired_steps.py")


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


EPISODE_HEADER = ("version,agent,scene_set,scene_seed,start_azimuth_rad,max_steps,steps,success,"
                  "final_occlusion_px,wall_time_s,end,message,azimuths_rad,elevations_rad\n")


def write_episodes(path, agent, steps_by_seed, max_steps=50):
    """steps_by_seed: {seed: steps, or None for a failure at the limit}."""
    lines = [EPISODE_HEADER]
    for seed, steps in steps_by_seed.items():
        success = steps is not None
        lines.append(f"2,{agent},s,{seed},0,{max_steps},{steps if success else max_steps},"
                     f"{int(success)},0,0.1,{'success' if success else 'step_limit'},,,\n")
    path.write_text("".join(lines))
    return path


def paired(*args):
    return subprocess.run([sys.executable, PAIRED_STEPS, *map(str, args)],
                          capture_output=True, text=True)


def test_paired_steps_counts_failures_at_the_limit_and_pairs_by_scene(tmp_path):
    base = write_episodes(tmp_path / "base.csv", "a", {1: 10, 2: 20, 3: 30, 4: 40})
    # Differences per scene: -2, +30 (a failure counted at 50), -10, -2; mean 4,
    # sd sqrt(944 / 3) = 17.74, standard error 17.74 / 2 = 8.87.
    other = write_episodes(tmp_path / "other.csv", "b", {4: 38, 3: 20, 2: None, 1: 8})
    folder = tmp_path / "out"
    folder.mkdir()
    write_episodes(folder / "set_episodes.csv", "oracle", {1: 5, 2: 10, 3: 15, 4: 20})
    result = paired(base, other, "--reference", folder)
    assert result.returncode == 0, result.stderr
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in result.stdout.splitlines() if line.startswith("| ") and "/" in line}
    assert rows[str(base)] == ["4", "4", "25.00", "", "2.000"]
    assert rows[str(other)] == ["4", "3", "29.00", "+4.00 ± 8.87", "2.320"]
    assert "reference " + str(folder) + ": 12.50 steps" in result.stdout


def test_paired_steps_refuses_different_scenes_and_mixed_agents(tmp_path):
    base = write_episodes(tmp_path / "base.csv", "a", {1: 10, 2: 20})
    fewer = write_episodes(tmp_path / "fewer.csv", "b", {1: 10})
    result = paired(base, fewer)
    assert result.returncode == 1
    assert "hold different episodes (1 and 2)" in result.stderr
    mixed = tmp_path / "mixed.csv"
    mixed.write_text(base.read_text() + "".join(
        line.replace(",a,", ",c,") for line in base.read_text().splitlines(True)[1:]))
    result = paired(mixed, base)
    assert result.returncode == 1
    assert "holds several agents (a, c): give --agent" in result.stderr
    result = paired(mixed, base, "--agent", "a")
    assert result.returncode == 0, result.stderr


def test_paired_steps_counts_moves_that_turn_back(tmp_path):
    # Scene 1 at the equator: east, east, west (180 deg), north (90 deg): one turn back of 3.
    # Scene 2 at 60 deg elevation: 0.2 rad of azimuth (0.1 on the sphere), then 0.2 rad back
    # and 0.1 down: 135 deg from the first once the azimuth is scaled (153 deg if it were not).
    lines = [EPISODE_HEADER,
             "2,a,s,1,0,50,4,1,0,0.1,success,,0;0.1;0.2;0.1;0.1,0;0;0;0;0.1\n",
             "2,a,s,2,0,50,2,1,0,0.1,success,,0;0.2;0,1.0471975511965976;1.0471975511965976;"
             "0.9471975511965976\n"]
    path = tmp_path / "paths.csv"
    path.write_text("".join(lines))
    result = paired(path, path, "--turn-backs", "120")
    assert result.returncode == 0, result.stderr
    assert "| moves turning back > 120 deg (episodes) |" in result.stdout
    assert result.stdout.count("| 2 of 4 (2) |") == 2
    result = paired(path, path, "--turn-backs", "140")
    assert result.stdout.count("| 1 of 4 (1) |") == 2, result.stdout
    without_paths = write_episodes(tmp_path / "no_paths.csv", "a", {1: 4, 2: 2})
    result = paired(without_paths, path, "--turn-backs", "120")
    assert result.returncode == 1
    assert "needs the paths" in result.stderr


def test_paired_steps_spreads_the_differences_and_pairs_two_agents_of_one_csv(tmp_path):
    # One CSV with both agents. Differences per scene: 0, +1, +2, +6, and a failure at the
    # limit (50 - 10 = +40): mean +9.80, standard error sqrt(1160.8 / 4) / sqrt(5) = 7.62;
    # 94 % of the summed excess (46 of 49) at +4 or more.
    both = write_episodes(tmp_path / "both.csv", "oracle", {1: 5, 2: 5, 3: 5, 4: 5, 5: 10})
    agent = write_episodes(tmp_path / "agent.csv", "escape", {1: 5, 2: 6, 3: 7, 4: 11, 5: None})
    both.write_text(both.read_text() + "".join(agent.read_text().splitlines(True)[1:]))
    result = paired(both, both, "--agent", "oracle", "--agent", "escape", "--spread")
    assert result.returncode == 0, result.stderr
    assert f"| {both} (escape) | 5 | 4 | 15.80 | +9.80 ± 7.62 |" in result.stdout
    assert f"| {both} (escape) | 0 | 1 | 1 | 1 | 0 | 0 | 1 | 1 | 94 % |" in result.stdout
    result = paired(both, both, both, "--agent", "oracle", "--agent", "escape")
    assert result.returncode == 2
    assert "give --agent once, or once per run (3), not 2 times" in result.stderr


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))


def load_script(name):
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        name, os.path.join(ROOT, "scripts", name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_robustness():
    return load_script("robustness")


def write_bridge_summary(folder, **fields):
    folder.mkdir()
    summary = {"scenes": "config/scenes/test_sweethome3d.yaml", "episodes": 50, "world": "room",
               "depth_sensor": "realsense_d435", "truly_clear": 49, "verdict_agrees": 47,
               "mean_steps": 19.26, "oracle_mean_steps": 7.66, "steps_over_oracle": 2.51}
    summary.update(fields)
    (folder / "bridge_summary.json").write_text(json.dumps(summary))
    return str(folder)


def test_bridge_rows_name_both_networks_and_rerun_each_summary(tmp_path):
    robustness = load_robustness()
    # Before --agent-model the agent ran the bridge's network: its command says so.
    old = write_bridge_summary(tmp_path / "old", model="runs/robust64/best.pt")
    split = write_bridge_summary(tmp_path / "split", model="shipped default",
                                 agent_model="runs/agent/best.pt")
    same = write_bridge_summary(tmp_path / "same", model="shipped default",
                                agent_model="shipped default")
    commands = robustness.bridge_commands([old, split, same])
    assert "--model runs/robust64/best.pt --agent-model runs/robust64/best.pt" in commands[0]
    assert "--model" not in commands[1].replace("--agent-model", "")
    assert "--agent-model runs/agent/best.pt" in commands[1]
    assert "--model" not in commands[2] and "--agent-model" not in commands[2]
    rows = robustness.bridge_rows([old, split, same]).splitlines()
    assert rows[2].startswith("| runs/robust64/best.pt |")
    assert rows[3].startswith(
        "| agent runs/agent/best.pt, bridge models/multitask_unet64_camera.pt |")
    assert "49 / 50 (98 %)" in rows[3]
    assert rows[4].startswith("| agent models/multitask_unet64_camera_agent.pt, "
                              "bridge models/multitask_unet64_camera.pt |")


def test_bridge_summaries_name_the_launch_defaults_they_ran(tmp_path):
    robustness = load_robustness()
    bridge_evaluation = load_script("bridge_evaluation")
    launch = open(os.path.join(ROOT, "launch", "bridge_evaluation.launch")).read()
    for default in (bridge_evaluation.DEFAULT_MODEL, bridge_evaluation.DEFAULT_AGENT_MODEL):
        assert "$(find occlusion_env)/" + default in launch, default
    new = write_bridge_summary(tmp_path / "new", model=bridge_evaluation.DEFAULT_MODEL,
                               model_is_default=True,
                               agent_model=bridge_evaluation.DEFAULT_AGENT_MODEL,
                               agent_model_is_default=True)
    command = robustness.bridge_commands([new])[0]
    assert "--model" not in command and "--agent-model" not in command
    row = robustness.bridge_rows([new]).splitlines()[2]
    assert row.startswith("| agent %s, bridge %s |" % (bridge_evaluation.DEFAULT_AGENT_MODEL,
                                                       bridge_evaluation.DEFAULT_MODEL))
    # A probability given on the command line is rerun with it.
    camera = write_bridge_summary(tmp_path / "camera", model="models/multitask_unet64_camera.pt",
                                  model_is_default=False, occlusion_probability=0.1,
                                  agent_model=bridge_evaluation.DEFAULT_AGENT_MODEL,
                                  agent_model_is_default=True)
    command = robustness.bridge_commands([camera])[0]
    assert "--model models/multitask_unet64_camera.pt --occlusion-probability 0.1 " in command
    assert "--agent-model" not in command


def test_robustness_table_of_some_conditions_without_agents():
    robustness = load_robustness()
    check = {"iou": 0.423, "escape_deg": 51.25, "frames": 300}
    results = {"randomised": {"a": {"check": check}, "b": {"check": dict(check, iou=0.1)}},
               "void, ideal": {"a": {"check": check}, "b": {"check": check}}}
    lines = robustness.markdown(results, [("a", "A.pt"), ("b", "B.pt")], []).splitlines()
    assert lines[0] == "| condition | IoU a | IoU b | escape error a | escape error b |"
    # In the conditions' own order, whatever the results' order; the others left out.
    assert lines[2] == "| void, ideal | 42.3 % | 42.3 % | 51.2 deg | 51.2 deg |"
    assert lines[3] == "| randomised | 42.3 % | 10.0 % | 51.2 deg | 51.2 deg |"
    assert len(lines) == 4


def test_derived_model_fields_keep_their_json_types():
    derive_model = load_script("derive_model")
    # A number must reach the manifest as one: the network's table reads view_crop and
    # view_field_of_view as numbers and refuses text.
    assert derive_model.number_or_text("1.0471975512") == 1.0471975512
    assert derive_model.number_or_text("0") == 0 and isinstance(derive_model.number_or_text("0"), int)
    assert derive_model.number_or_text("filled") == "filled"


PPO_RATE = os.path.join(ROOT, "scripts", "ppo_rate.py")


def write_updates(run, seconds_per_update):
    run.mkdir()
    lines = ["update,env_steps,seconds,environment_seconds,inference_seconds,"
             "optimisation_seconds"]
    seconds = 0.0
    for update, dt in enumerate(seconds_per_update, start=1):
        seconds += dt
        lines.append(f"{update},{200 * update},{seconds},{dt / 2},{dt / 4},{dt / 4}")
    (run / "updates.csv").write_text("\n".join(lines) + "\n")


def test_ppo_rate_is_the_median_over_the_updates_asked_for(tmp_path):
    # Updates 2-5 take 1, 2, 4 and 1 s for 200 steps each; from update 3: 100, 50, 200 steps/s.
    write_updates(tmp_path / "run", [9.0, 1.0, 2.0, 4.0, 1.0])
    out = subprocess.run([sys.executable, PPO_RATE, tmp_path / "run", "--from-update", "3",
                          "--label", "two envs"], capture_output=True, text=True, check=True)
    assert out.stdout.splitlines()[-1] == "| two envs | 100 | 50 % | 25 % | 25 % | 3 |"
    # Nothing from update 9 on: refused, not a row of nothing.
    failed = subprocess.run([sys.executable, PPO_RATE, tmp_path / "run", "--from-update", "9"],
                            capture_output=True, text=True)
    assert failed.returncode == 1 and "no update from 9" in failed.stderr


STOPPING_RULES = os.path.join(ROOT, "scripts", "stopping_rules.py")


def write_views(path, episodes):
    """episodes: {seed: [(true_px, px at 0.01, px at 0.2), ...]}, the start view first."""
    lines = ["seed,step,true_px,estimated_px_at_0.01,estimated_px_at_0.2"]
    for seed, views in episodes.items():
        lines += [f"{seed},{step},{true},{low},{high}"
                  for step, (true, low, high) in enumerate(views)]
    path.write_text("\n".join(lines) + "\n")


# Scene 1: clear at 0.2 from step 1 on, truly clear from step 2 on; nothing ever below 0.01
# except step 3. Scene 2: never clear at 0.2, truly clear at step 2, sure (0 at 0.01) at 2.
TWO_SCENES = {
    1: [(9, 9, 9), (3, 5, 0), (0, 5, 0), (0, 0, 0), (0, 5, 0)],
    2: [(9, 9, 9), (4, 5, 5), (0, 0, 5), (0, 5, 5), (0, 5, 5)],
}


def test_stopping_rules_stop_at_the_first_level_that_confirms(tmp_path):
    views = tmp_path / "views.csv"
    write_views(views, TWO_SCENES)
    result = subprocess.run([sys.executable, STOPPING_RULES, views, "--baseline", "0.2,0,2",
                             "--need", "1.0", "--views", "1,2", "--thresholds", "0",
                             "--max-steps", "4", "--top", "50"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    rows = {line.split("|")[1].strip(): line.split("|")[2].strip()
            for line in result.stdout.splitlines() if line.startswith("| (")}
    # The baseline: scene 1 stops at step 2 (clear), scene 2 never (counted at 4): 1 / 0 / 1.
    assert rows["(0.2, 0, 2)"] == "1 / 0 / 1, 3.00"
    # Sure views stop scene 2 at once at step 2, scene 1 at step 3: both truly clear.
    assert rows["(0.01, 0, 1)"] == "2 / 0 / 0, 2.50"
    # Two levels: whichever confirms first (scene 1 at step 2 by 0.2, scene 2 at step 2).
    assert rows["(0.01, 0, 1) + (0.2, 0, 2)"] == "2 / 0 / 0, 2.00"
    # (0.2, 0, 1) stops scene 1 at step 1, too early, so it is not among the rules shown.
    assert "(0.2, 0, 1)" not in rows
    assert "first truly clear view after 2.00 steps" in result.stdout


def test_stopping_rules_one_level_tries_only_the_bridges_rules(tmp_path):
    # TWO_SCENES: the two-level rule that stops both scenes at step 2 is left
    # out; the one-level rules that stop both on a clear view remain.
    views = tmp_path / "views.csv"
    write_views(views, TWO_SCENES)
    result = subprocess.run([sys.executable, STOPPING_RULES, views, "--baseline", "0.2,0,2",
                             "--need", "1.0", "--views", "1,2", "--thresholds", "0",
                             "--max-steps", "4", "--top", "50", "--one-level"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    rows = [line.split("|")[1].strip() for line in result.stdout.splitlines()
            if line.startswith("| (")]
    assert rows == ["(0.2, 0, 2)", "(0.01, 0, 1)"]  # the baseline, then the only one chosen
    both = subprocess.run([sys.executable, STOPPING_RULES, views, "--one-level", "--also", views],
                          capture_output=True, text=True)
    assert both.returncode != 0 and "--one-level" in both.stderr


def test_stopping_rules_count_false_alarms_by_views_clear_before(tmp_path):
    # Scene 3: truly clear at step 1, occluded at 2, clear again at 3 and 4; the estimate at 0.2
    # calls steps 1 and 3 occluded (9 px > 0), step 4 clear. An occluded view restarts the count.
    views = tmp_path / "views.csv"
    write_views(views, {3: [(9, 9, 9), (0, 0, 9), (5, 0, 9), (0, 0, 9), (0, 0, 0)]})
    result = subprocess.run([sys.executable, STOPPING_RULES, views, "--baseline", "0.2,0,2",
                             "--views", "1", "--thresholds", "0", "--max-steps", "4"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    rows = {line.split("|")[1].strip(): line.split("|")[2].strip()
            for line in result.stdout.splitlines()
            if line.startswith("| ") and " of " in line}
    assert rows["0"] == "2 of 2 (100 %)"
    assert rows["1"] == "0 of 1 (0 %)"
    assert rows["2"] == "0 of 0"
    assert rows[">= 5"] == "0 of 0"


def test_stopping_rules_with_a_second_estimate_stop_where_both_call_views_clear(tmp_path):
    # The first estimate calls step 1 clear at 0.2 while it holds 3 px; the second (the same
    # path's views) still sees 7 px there and calls step 2 clear.
    first, second = tmp_path / "first.csv", tmp_path / "second.csv"
    write_views(first, {1: [(9, 9, 9), (3, 5, 0), (0, 5, 0), (0, 5, 0)]})
    write_views(second, {1: [(9, 9, 9), (3, 9, 7), (0, 9, 0), (0, 9, 0)]})
    command = [sys.executable, STOPPING_RULES, first, "--baseline", "0.2,0,1", "--need", "1.0",
               "--views", "1", "--thresholds", "0", "--max-steps", "4", "--top", "50"]
    result = subprocess.run(command + ["--also", second], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    rows = {line.split("|")[1].strip(): line.split("|")[2].strip()
            for line in result.stdout.splitlines() if line.startswith("| (")}
    assert rows["(0.2, 0, 1)"] == "0 / 1 / 0, 1.00"  # the baseline, alone: too early
    assert rows["(0.2, 0) & (0.2, 0) px, 1 views"] == "1 / 0 / 0, 2.00"
    assert "(0.01, 0) & (0.2, 0) px, 1 views" not in rows  # never stops: not all clear
    # Views of another path are refused, not paired.
    write_views(second, {1: [(9, 9, 9), (0, 9, 7), (0, 9, 0), (0, 9, 0)]})
    result = subprocess.run(command + ["--also", second], capture_output=True, text=True)
    assert result.returncode == 1 and "not the views of the same paths" in result.stderr


def test_stopping_rules_refuses_a_file_without_estimates(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("seed,step,true_px\n1,0,5\n")
    result = subprocess.run([sys.executable, STOPPING_RULES, bad], capture_output=True, text=True)
    assert result.returncode == 1
    assert "not a --views-csv file" in result.stderr
    empty = tmp_path / "empty.csv"
    write_views(empty, {})
    result = subprocess.run([sys.executable, STOPPING_RULES, empty], capture_output=True, text=True)
    assert result.returncode == 1
    assert "no views" in result.stderr


SPLIT_BY_CAMERA = os.path.join(ROOT, "scripts", "split_by_camera.py")


def write_scene(dataset, index, world, sensor, fov_deg, width):
    folder = dataset / "train" / f"{index:06d}"
    folder.mkdir(parents=True)
    camera = {"field_of_view_rad": fov_deg * 3.141592653589793 / 180.0, "width": width,
              "height": width, "radius_m": 1.0}
    labels = {str(i): {"world": world, "depth_sensor": sensor, "camera": camera}
              for i in range(2)}
    (folder / "scene_labels.json").write_text(json.dumps(labels))


def split(*args):
    return subprocess.run([sys.executable, SPLIT_BY_CAMERA, *map(str, args)],
                          capture_output=True, text=True)


def test_scenes_are_split_by_their_camera_and_linked_not_copied(tmp_path):
    dataset = tmp_path / "data"
    write_scene(dataset, 0, "void", "ideal", 61.0, 64)
    write_scene(dataset, 1, "room", "ideal", 79.9, 100)
    write_scene(dataset, 2, "void", "realsense_d435", 80.0, 128)
    (dataset / "dataset.json").write_text('{"scenes": []}')
    result = split(dataset, tmp_path / "fov", "--by", "field_of_view")
    assert result.returncode == 0, result.stderr
    groups = {p.name: sorted(s.name for s in (p / "train").iterdir())
              for p in (tmp_path / "fov").iterdir()}
    assert groups == {"fov_60-70": ["000000"], "fov_70-80": ["000001"], "fov_80-90": ["000002"]}
    link = tmp_path / "fov" / "fov_70-80" / "train" / "000001"
    assert link.is_symlink() and link.resolve() == (dataset / "train" / "000001").resolve()
    assert (tmp_path / "fov" / "fov_70-80" / "dataset.json").read_text() == '{"scenes": []}'
    assert "| fov_80-90 | 1 |" in result.stdout
    result = split(dataset, tmp_path / "both", "--by", "world", "--by", "width",
                   "--width-band", "64")
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in (tmp_path / "both").iterdir()) == [
        "room_width_64-128px", "void_width_128-192px", "void_width_64-128px"]


def test_a_split_refuses_an_existing_folder_and_labels_without_a_camera(tmp_path):
    dataset = tmp_path / "data"
    write_scene(dataset, 0, "void", "ideal", 60.0, 64)
    (dataset / "dataset.json").write_text("{}")
    (tmp_path / "out").mkdir()
    result = split(dataset, tmp_path / "out", "--by", "world")
    assert result.returncode != 0 and "exists; give a new folder" in result.stderr
    old = tmp_path / "old"
    (old / "train" / "000000").mkdir(parents=True)
    (old / "train" / "000000" / "scene_labels.json").write_text('{"0": {"oracle_steps": 1}}')
    (old / "dataset.json").write_text("{}")
    result = split(old, tmp_path / "split", "--by", "radius")
    assert result.returncode != 0 and "do not record the camera" in result.stderr
    assert not (tmp_path / "split").exists()


CROP_TO_FIELD_OF_VIEW = os.path.join(ROOT, "scripts", "crop_to_field_of_view.py")


def test_frames_are_cropped_to_the_field_of_view_around_their_principal_point(tmp_path):
    import numpy as np
    from PIL import Image
    dataset = tmp_path / "data"
    scene = dataset / "train" / "000000"
    for folder in ("rgb", "depth", "occlusion", "mask", "mask_visib"):
        (scene / folder).mkdir(parents=True)
    (dataset / "dataset.json").write_text("{}")
    # 90 deg at 64 px: fx = 32; the 60 deg view is 2 * 32 * tan(30 deg) = 36.95 -> 37 px wide,
    # centred on (cx, cy) = (33, 31): columns 15..51, rows 13..49.
    camera = {"width": 64, "height": 64, "fx": 32.0, "fy": 32.0, "cx": 33.0, "cy": 31.0,
              "field_of_view_rad": 3.141592653589793 / 2}
    (scene / "scene_labels.json").write_text(json.dumps({"0": {"camera": camera}}))
    (scene / "scene_camera.json").write_text(json.dumps(
        {"0": {"cam_K": [32.0, 0, 33.0, 0, 32.0, 31.0, 0, 0, 1], "depth_scale": 0.25}}))
    rgb = np.zeros((64, 64, 3), np.uint8)
    rgb[13, 15] = (255, 0, 0)
    Image.fromarray(rgb).save(scene / "rgb" / "000000.png")
    depth = np.full((64, 64), 4000, np.uint16)
    depth[49, 51] = 1234
    Image.fromarray(depth).save(scene / "depth" / "000000.png")
    occlusion = np.zeros((64, 64), np.uint8)
    occlusion[20, 20] = occlusion[0, 0] = 255  # one inside the crop, one left out
    Image.fromarray(occlusion).save(scene / "occlusion" / "000000.png")
    Image.fromarray(occlusion).save(scene / "mask" / "000000_000000.png")
    result = subprocess.run([sys.executable, CROP_TO_FIELD_OF_VIEW, dataset, tmp_path / "out"],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "1 of 1 frames cropped to 60 deg; occluded pixels left out: 1 of 2 (50.00 %)" \
        in result.stdout
    out = tmp_path / "out" / "train" / "000000"
    cropped_rgb = np.array(Image.open(out / "rgb" / "000000.png"))
    assert cropped_rgb.shape == (37, 37, 3)
    assert tuple(cropped_rgb[0, 0]) == (255, 0, 0)
    cropped_depth = np.array(Image.open(out / "depth" / "000000.png"))
    assert cropped_depth[36, 36] == 1234 and cropped_depth[0, 0] == 4000
    assert np.array(Image.open(out / "mask" / "000000_000000.png"))[7, 5] == 255
    labels = json.loads((out / "scene_labels.json").read_text())["0"]["camera"]
    assert (labels["width"], labels["height"], labels["cx"], labels["cy"]) == (37, 37, 18.0, 18.0)
    matrix = json.loads((out / "scene_camera.json").read_text())["0"]["cam_K"]
    assert (matrix[2], matrix[5]) == (18.0, 18.0)
    again = subprocess.run([sys.executable, CROP_TO_FIELD_OF_VIEW, dataset, tmp_path / "out"],
                           capture_output=True, text=True)
    assert again.returncode != 0 and "exists" in again.stderr


DEPTH_COVERAGE = os.path.join(ROOT, "scripts", "depth_coverage.py")


def test_depth_coverage_counts_unread_pixels_overall_and_under_the_occlusion_label(tmp_path):
    import numpy as np
    from PIL import Image
    dataset = tmp_path / "data"
    for scene in ("000000", "000001"):
        for folder in ("depth", "occlusion"):
            (dataset / "train" / scene / folder).mkdir(parents=True)
    # Two 10 x 10 frames: 200 pixels, 30 of them unread; 8 occluded, 3 of those unread.
    depth = np.full((10, 10), 4000, np.uint16)
    depth[0, :] = 0           # 10 unread, none occluded
    depth[5, 0:3] = 0         # 3 unread, all occluded
    occlusion = np.zeros((10, 10), np.uint8)
    occlusion[5, 0:5] = 255   # 5 occluded
    Image.fromarray(depth).save(dataset / "train" / "000000" / "depth" / "000000.png")
    Image.fromarray(occlusion).save(dataset / "train" / "000000" / "occlusion" / "000000.png")
    depth = np.full((10, 10), 1234, np.uint16)
    depth[9, :] = depth[8, 3:10] = 0  # 17 unread
    occlusion = np.zeros((10, 10), np.uint8)
    occlusion[2, 2:5] = 255   # 3 occluded, all read
    Image.fromarray(depth).save(dataset / "train" / "000001" / "depth" / "000000.png")
    Image.fromarray(occlusion).save(dataset / "train" / "000001" / "occlusion" / "000000.png")
    result = subprocess.run([sys.executable, DEPTH_COVERAGE, dataset], capture_output=True,
                            text=True)
    assert result.returncode == 0, result.stderr
    assert "| %s | 2 | 15.0 %% | 37.5 %% |" % dataset in result.stdout
    empty = tmp_path / "empty"
    empty.mkdir()
    result = subprocess.run([sys.executable, DEPTH_COVERAGE, empty], capture_output=True,
                            text=True)
    assert result.returncode != 0 and "no frames under" in result.stderr


PLOT_IOU_BY_RADIUS = os.path.join(ROOT, "scripts", "plot_iou_by_radius.py")


def write_check(tmp_path, name, sensor, radius_range, iou, model="m.pt", randomize=True):
    dataset = tmp_path / name
    dataset.mkdir()
    options = {"randomize": randomize, "world": "room", "depth_sensor": sensor,
               "camera_randomization": {"radius_range": radius_range}}
    (dataset / "dataset.json").write_text(json.dumps({"options": options}))
    check = tmp_path / (name + ".json")
    check.write_text(json.dumps({"model": model, "datasets": [str(dataset)],
                                 "figures": {"val_iou": iou,
                                             "val_iou_95": [iou - 0.02, iou + 0.01]}}))
    return check


def test_iou_by_radius_is_tabled_per_sensor_from_the_datasets_options(tmp_path):
    checks = [write_check(tmp_path, "far_ideal", "ideal", [1.0, 1.5], 0.48),
              write_check(tmp_path, "near_azure", "azure_kinect", [0.5, 1.0], 0.35),
              write_check(tmp_path, "near_ideal", "ideal", [0.5, 1.0], 0.47)]
    result = subprocess.run([sys.executable, PLOT_IOU_BY_RADIUS, *map(str, checks)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "| world, depth sensor | 0.5-1 m | 1-1.5 m |"
    assert lines[2] == "| room, azure_kinect | 35.0 (33.0-36.0) |  |"
    assert lines[3] == "| room, ideal | 47.0 (45.0-48.0) | 48.0 (46.0-49.0) |"
    other = write_check(tmp_path, "other_model", "ideal", [0.5, 1.0], 0.4, model="n.pt")
    result = subprocess.run([sys.executable, PLOT_IOU_BY_RADIUS, str(checks[0]), str(other)],
                            capture_output=True, text=True)
    assert result.returncode != 0 and "2 models" in result.stderr
    fixed = write_check(tmp_path, "fixed", "ideal", [0.5, 1.0], 0.4, randomize=False)
    result = subprocess.run([sys.executable, PLOT_IOU_BY_RADIUS, str(fixed)],
                            capture_output=True, text=True)
    assert result.returncode != 0 and "not made with --randomize" in result.stderr
