#!/usr/bin/env python3
"""Compute the visual meshes of the packaged robots once and store them in the package.

    .venv/bin/python tools/authoring/build_meshes.py              # write robokin/models/mesh_data/<robot>-<budget>.npz
    .venv/bin/python tools/authoring/build_meshes.py ur10 panda   # only these robots

Reading and decimating a robot's mesh files (robokin.models.visual_meshes) costs about
3 s of CPU; the robots of robokin.models.mesh_store.STORED_ROBOTS, at the default budget
DEFAULT_MESH_BYTES, are read from the stored files instead. Run this after changing the
mesh pipeline (robokin/models/urdf_meshes.py), the budget, or example-robot-data:
tests/test_meshes_stored.py fails until the stored files equal a fresh computation, and
visual_meshes warns (MeshWarning) and computes afresh when the source files differ.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robokin.models.mesh_store import STORED_ROBOTS, write_record
from robokin.models.urdf_meshes import DEFAULT_MESH_BYTES, mesh_record, packaged_meshes


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", metavar="ROBOT",
                        help=f"robots to store (default: all of {', '.join(STORED_ROBOTS)})")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.robots) - set(STORED_ROBOTS))
    if unknown:
        parser.error(f"unknown robot(s) {', '.join(unknown)}; stored robots: {', '.join(STORED_ROBOTS)}")
    for robot in args.robots or list(STORED_ROBOTS):
        meshes, chain, files = packaged_meshes(robot, DEFAULT_MESH_BYTES)
        path = write_record(mesh_record(meshes, chain, robot, DEFAULT_MESH_BYTES), files)
        print(f"{path.relative_to(Path.cwd()) if path.is_relative_to(Path.cwd()) else path}: {meshes.triangles} "
              f"triangles, {meshes.nbytes:,} bytes of arrays, {path.stat().st_size:,} bytes stored")
    return 0


if __name__ == "__main__":
    sys.exit(main())
