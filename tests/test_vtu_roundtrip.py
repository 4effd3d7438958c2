"""The VTU/PVD outputs read back with a real VTK reader."""

from __future__ import annotations

import xml.etree.ElementTree as ET

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
