#!/usr/bin/env python3
"""Compares two episode CSVs (version 1 or 2, agents/episode.hpp) row by row on every column the
two share except wall_time_s (timing differs between runs); exits 1 on any difference.
Usage: compare_episode_csvs.py OLD.csv NEW.csv"""
import csv
import sys


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    old, new = rows(sys.argv[1]), rows(sys.argv[2])
    if len(old) != len(new):
        print(f"{len(old)} rows against {len(new)}")
        return 1
    shared = [c for c in old[0] if c in new[0] and c not in ("wall_time_s", "version")]
    differences = 0
    for i, (a, b) in enumerate(zip(old, new), start=2):
        for column in shared:
            if a[column] != b[column]:
                differences += 1
                if differences <= 10:
                    print(f"line {i}, {column}: {a[column]!r} != {b[column]!r}")
    print(f"{sys.argv[2]}: {len(new)} rows, columns compared: {', '.join(shared)}; "
          f"{differences} differences")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
