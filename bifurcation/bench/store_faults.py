"""Fault injection into a store: random single-bit flips, deleted and truncated chunks.

    python -m bifurcation.bench.store_faults [--flips 100] [--losses 20] [--seed 1] [--workers 2]

Writes a clean store of a 2-law × 64 ν_f × 64 ν grid (tiles 8 × 8: 128 tiles of 9 arrays, 1152 data chunks and 3 coordinate chunks) in this
process, flips ``--flips`` random single bits (each in a different chunk file, any array: data, ``done``
or a coordinate), deletes or truncates ``--losses`` other chunk files, then checks that

* ``verify`` reports every damaged chunk's tile (or the coordinate chunk) and no other,
* ``query`` refuses (one line, exit 2) and prints no value,
* ``verify --repair`` leaves a sound store equal bit for bit to the clean one.

Prints one JSON object with the counts. Not a test: it takes a minute or two on two cores.
"""

from __future__ import annotations

import argparse
import json
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def chunk_files(store: Path) -> list[Path]:
    """Every chunk file of the store (not metadata, not the lock)."""
    return sorted(p for p in store.rglob("*") if p.is_file() and "c" in p.relative_to(store).parts[1:2])


def flip_bit(path: Path, rng: random.Random) -> None:
    data = bytearray(path.read_bytes())
    bit = rng.randrange(8 * len(data))
    data[bit // 8] ^= 1 << (bit % 8)
    path.write_bytes(bytes(data))


def lose(path: Path, rng: random.Random) -> str:
    if rng.random() < 0.5:
        path.unlink()
        return "deleted"
    data = path.read_bytes()
    path.write_bytes(data[:rng.randrange(len(data))])
    return "truncated"


def tile_of(store: Path, path: Path) -> tuple:
    parts = path.relative_to(store).parts   # name / c / k0 / k1 / ...
    return tuple(int(k) for k in parts[2:])


def main(argv=None) -> dict:
    from bifurcation.run.repair import verify
    from bifurcation.store import create_store, open_store, write_tile
    from bifurcation.run.tiles import OUTPUTS, compute_tile, iter_tiles
    from bifurcation.workflow import Workflow
    from bifurcation.workflow._axes import linear_points, log_points

    parser = argparse.ArgumentParser()
    parser.add_argument("--flips", type=int, default=100)
    parser.add_argument("--losses", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    w = Workflow(name="faults", laws=("piecewise-linear", "carlson-langer"), nu=log_points(1e-3, 1e-12, 64),
                 nu_f=linear_points(0.05, 0.95, 64), tiles=(8, 8))
    with tempfile.TemporaryDirectory(prefix="bifurcation-faults-") as tmp:
        store = Path(tmp) / "s.zarr"
        run_id = create_store(store, w)["run_id"]
        for tile in iter_tiles(w):
            write_tile(store, tile, compute_tile(tile), run_id)
        clean = {name: np.asarray(open_store(store)[name].values) for name in OUTPUTS}
        files = chunk_files(store)
        victims = rng.sample(files, args.flips + args.losses)
        kinds = {"flipped": 0, "deleted": 0, "truncated": 0}
        expected = set()   # (array, tile) of each damaged chunk
        for k, path in enumerate(victims):
            name = path.relative_to(store).parts[0]
            expected.add((name, tile_of(store, path)))
            if k < args.flips:
                flip_bit(path, rng)
                kinds["flipped"] += 1
            else:
                kinds[lose(path, rng)] += 1
        t0 = time.perf_counter()
        report = verify(store)
        verify_s = time.perf_counter() - t0
        coords = {"law", "nu", "nu_f"}
        want_tiles = {t for n, t in expected if n not in coords}
        want_coords = {(n, t) for n, t in expected if n in coords}
        found_tiles = {d.tile for d in report.damage if len(d.tile) > 1}
        found_coords = {(d.chunk.split("/")[0], d.tile) for d in report.damage if len(d.tile) == 1}
        query = subprocess.run([sys.executable, "-m", "bifurcation", "query", "--store", str(store),
                                "--format", "csv"], capture_output=True, text=True)
        t0 = time.perf_counter()
        repaired = verify(store, repair=True, workers=args.workers, progress=False)
        repair_s = time.perf_counter() - t0
        after = {name: np.asarray(open_store(store)[name].values) for name in OUTPUTS}
        identical = all(np.array_equal(after[n].view(np.uint8), clean[n].view(np.uint8)) for n in OUTPUTS)
        out = {
            "chunks": len(files), "tiles": report.tiles, "injected": kinds,
            "damaged_tiles_injected": len(want_tiles), "damaged_tiles_found": len(found_tiles),
            "coordinate_chunks_injected": len(want_coords), "coordinate_chunks_found": len(found_coords),
            "all_detected": want_tiles <= found_tiles and want_coords <= found_coords,
            "false_alarms": len(found_tiles - want_tiles) + len(found_coords - want_coords),
            "query_exit": query.returncode, "query_stdout_bytes": len(query.stdout),
            "query_stderr": query.stderr.strip(),
            "repaired_tiles": repaired.repaired_tiles, "damage_after_repair": len(repaired.after),
            "bit_identical_to_clean": identical, "verify_s": round(verify_s, 2), "repair_s": round(repair_s, 2),
        }
    print(json.dumps(out, indent=2))
    return out


if __name__ == "__main__":
    main()
