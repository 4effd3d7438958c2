"""The VTU/PVD outputs read back with a real VTK reader."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from pathlib import Path

import numpy as np
import pytest

import nmm3d

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402


def read_vtu(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(path))
    r.Update()
    return r.GetOutput()


def polyhedra_volume(grid) -> float:
    f = vtk.vtkCellSizeFilter()
    f.SetInputData(grid)
    f.ComputeVolumeOn()
    f.Update()
    return float(vtk_to_numpy(f.GetOutput().GetCellData().GetArray("Volume")).sum())


def test_frames_are_polyhedra_with_fields(cube, tmp_path):
    cube["cover"]["rotation"] = [10.0, 20.0, 30.0]
    result = nmm3d.Scenario.from_dict(cube).run(out=tmp_path / "run")
    pvd = ET.parse(tmp_path / "run" / "result.pvd").getroot()
    datasets = pvd.findall("./Collection/DataSet")
    assert [float(d.get("timestep")) for d in datasets] == pytest.approx([0.0, 0.05, 0.1])
    last = read_vtu(tmp_path / "run" / datasets[-1].get("file"))
    assert last.GetNumberOfCells() == result.summary["manifold_elements"]
    assert {last.GetCellType(i) for i in range(last.GetNumberOfCells())} == {vtk.VTK_POLYHEDRON}
    assert polyhedra_volume(last) == pytest.approx(1.0, rel=1e-9)
    disp = vtk_to_numpy(last.GetPointData().GetArray("displacement"))
    np.testing.assert_allclose(disp[:, 2], -0.05, rtol=1e-9)
    stress = vtk_to_numpy(last.GetCellData().GetArray("stress"))
    assert stress.shape == (last.GetNumberOfCells(), 6)
    assert np.abs(stress).max() < 1.0
    assert set(vtk_to_numpy(last.GetCellData().GetArray("block_id")).tolist()) == {0}


def test_contact_frames_hold_points_forces_and_states(tmp_path):
    """A cube resting on a fixed slab: the contact frame's normal forces carry its weight."""
    scenario = {
        "analysis": {"kind": "static", "duration": 1.0e3, "dt": 0.01, "max_steps": 50, "gravity": [0.0, 0.0, -10.0],
                     "output_interval": 0.0},
        "cover": {"pattern": "tet6", "size": 0.5},
        "material": [{"name": "rock", "density": 2500.0, "young": 1.0e10, "poisson": 0.0}],
        "joint": [{"name": "j", "friction_angle": 30.0}],
        "body": [
            {"name": "base", "material": "rock", "fixed": True, "shape": {"box": {"min": [-2, -2, -1], "max": [2, 2, 0]}}},
            {"name": "cube", "material": "rock", "joint": "j", "shape": {"box": {"min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 1]}}},
        ],
    }
    result = nmm3d.Scenario.from_dict(scenario).run(out=tmp_path / "run")
    assert result.completed, result.summary["message"]
    pvd = ET.parse(tmp_path / "run" / "result.pvd").getroot()
    parts = [d for d in pvd.findall("./Collection/DataSet") if d.get("part") == "1"]
    assert len(parts) == 2  # first and last frame
    grid = read_vtu(tmp_path / "run" / parts[-1].get("file"))
    n = grid.GetNumberOfPoints()
    assert n == grid.GetNumberOfCells() >= 4
    assert {grid.GetCellType(i) for i in range(n)} == {vtk.VTK_VERTEX}
    data = grid.GetPointData()
    normal = vtk_to_numpy(data.GetArray("normal"))
    np.testing.assert_allclose(normal, np.tile([0.0, 0.0, 1.0], (n, 1)), atol=1e-12)
    # Σ normal forces on the cube = its weight (static equilibrium); the shear forces are local
    # (the elastic faces' in-plane strain held by friction) and balance each other.
    weight = 2500.0 * 10.0
    assert vtk_to_numpy(data.GetArray("normal_force")).sum() == pytest.approx(weight, rel=1e-5)
    shear = vtk_to_numpy(data.GetArray("shear_force"))
    assert np.abs(shear.sum(axis=0)).max() < 1e-5 * weight
    assert np.abs(shear).max() < 0.01 * weight
    assert set(vtk_to_numpy(data.GetArray("state")).tolist()) == {1}  # stick
    assert vtk_to_numpy(data.GetArray("area")).sum() == pytest.approx(1.0, rel=1e-6)  # on the deformed faces
    assert set(vtk_to_numpy(data.GetArray("block_a")).tolist()) == {1}


def test_meshio_and_pyvista_read_first_and_last_frames(tmp_path):
    """Issue 14: every tool reads our frames; geometry is current, reference = current − u."""
    meshio = pytest.importorskip("meshio")
    pv = pytest.importorskip("pyvista")
    root = Path(__file__).resolve().parents[1]
    scenario = nmm3d.load(root / "examples" / "incline.toml")
    result = scenario.run(out=tmp_path / "run")
    scenario.write_blocks(tmp_path / "blocks")
    frames = sorted((tmp_path / "run" / "frames").glob("blocks_*.vtu"))
    for f in (frames[0], frames[-1]):
        m = meshio.read(f)
        assert sum(len(c.data) for c in m.cells) == result.summary["manifold_elements"]
        np.testing.assert_allclose(m.points - m.point_data["displacement"], m.point_data["reference_position"],
                                   atol=1e-9)
        assert pv.read(f).n_cells == result.summary["manifold_elements"]
    contacts = sorted((tmp_path / "run" / "frames").glob("contacts_*.vtu"))
    assert len(meshio.read(contacts[-1]).points) > 0
    for f in frames + contacts:
        same_arrays(meshio.read(f), read_vtu(f))
    blocks = meshio.read(tmp_path / "blocks" / "blocks.vtu")
    assert sum(len(v) for v in blocks.cell_data["volume"]) == sum(len(c.data) for c in blocks.cells)


def same_arrays(m, grid) -> None:
    """meshio's arrays equal VTK's, value for value (meshio 5.3 once handed one array's data to
    another when an offset it made equalled a later raw offset: a third of the contact frames)."""
    for name, values in m.point_data.items():
        expected = vtk_to_numpy(grid.GetPointData().GetArray(name))
        np.testing.assert_array_equal(np.asarray(values).reshape(expected.shape), expected, err_msg=name)
    for name, blocks in m.cell_data.items():
        expected = vtk_to_numpy(grid.GetCellData().GetArray(name))
        np.testing.assert_array_equal(np.concatenate(blocks).reshape(expected.shape), expected, err_msg=name)


def test_meshio_reads_contact_frames_of_every_size(tmp_path):
    """Contact frames of n = 1, 2, … points (n mod 3 decided where meshio's offsets collided):
    meshio and VTK read the same values."""
    meshio = pytest.importorskip("meshio")
    scenario = nmm3d.load(Path(__file__).resolve().parents[1] / "examples" / "dominos.toml",
                          ["analysis.duration=0.6", "analysis.output_interval=0.02"])
    scenario.run(out=tmp_path / "run")
    contacts = sorted((tmp_path / "run" / "frames").glob("contacts_*.vtu"))
    sizes = set()
    for f in contacts:
        m = meshio.read(f)
        sizes.add(len(m.points) % 3)
        same_arrays(m, read_vtu(f))
    assert sizes == {0, 1, 2}, sizes
