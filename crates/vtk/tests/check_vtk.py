#!/usr/bin/env python3
"""Independent check of foamgrain's VTK files with VTK's own XML readers (what ParaView uses).

Usage: check_vtk.py FILE.vtu|FILE.vtp|FILE.vtk|FILE.pvd  (.vtk: legacy PolyData)

Prints one JSON object on stdout:
  vtk_version, errors (messages VTK printed while reading; must be empty),
  n_points, n_cells, cell_types ({type: count}), points (list of [x, y, z]),
  point_data / cell_data ({name: {components, range, values}}),
  for .vtu also volumes (per cell, from vtkCellSizeFilter), total_volume, and
  face_volumes (per cell, divergence theorem over the faces VTK reports for the cell,
  cell.GetFace(i): positive only if VTK sees the faces oriented outward),
  for .vtp and .vtk also n_verts,
  for .pvd: datasets ([{timestep, part, file, n_points, n_cells}]) each read with VTK.
Exit status 0 when the file was read, 1 when VTK reported an error, 2 on usage errors.
"""

import json
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def capture_messages():
    window = vtk.vtkStringOutputWindow()
    vtk.vtkOutputWindow.SetInstance(window)
    return window


def read(path):
    if path.endswith(".vtu"):
        reader = vtk.vtkXMLUnstructuredGridReader()
    elif path.endswith(".vtp"):
        reader = vtk.vtkXMLPolyDataReader()
    elif path.endswith(".vtk"):
        reader = vtk.vtkPolyDataReader()
    else:
        raise SystemExit(f"unsupported file type: {path}")
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def arrays(data):
    out = {}
    for i in range(data.GetNumberOfArrays()):
        a = data.GetArray(i)
        n, k = a.GetNumberOfTuples(), a.GetNumberOfComponents()
        values = [list(a.GetTuple(t)) if k > 1 else a.GetTuple(t)[0] for t in range(n)]
        out[a.GetName()] = {
            "components": k,
            "type": a.GetDataTypeAsString(),
            "range": list(a.GetRange(-1 if k > 1 else 0)),
            "values": values,
        }
    return out


def face_volume(cell, points):
    """Signed volume by the divergence theorem over the cell's faces as VTK reports them."""
    vol = 0.0
    for f in range(cell.GetNumberOfFaces()):
        face = cell.GetFace(f)
        ids = [face.GetPointId(i) for i in range(face.GetNumberOfPoints())]
        p0 = points.GetPoint(ids[0])
        for a, b in zip(ids[1:-1], ids[2:]):
            p1, p2 = points.GetPoint(a), points.GetPoint(b)
            vol += (
                p0[0] * (p1[1] * p2[2] - p1[2] * p2[1])
                - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0])
                + p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])
            ) / 6.0
    return vol


def summary(path):
    ds = read(path)
    out = {
        "n_points": ds.GetNumberOfPoints(),
        "n_cells": ds.GetNumberOfCells(),
        "points": [list(ds.GetPoint(i)) for i in range(ds.GetNumberOfPoints())],
        "point_data": arrays(ds.GetPointData()),
        "cell_data": arrays(ds.GetCellData()),
    }
    types = {}
    for c in range(ds.GetNumberOfCells()):
        t = ds.GetCellType(c)
        types[str(t)] = types.get(str(t), 0) + 1
    out["cell_types"] = types
    out["cell_type_list"] = [ds.GetCellType(c) for c in range(ds.GetNumberOfCells())]
    if path.endswith(".vtu"):
        sizes = vtk.vtkCellSizeFilter()
        sizes.SetInputData(ds)
        sizes.ComputeVertexCountOff()
        sizes.ComputeLengthOff()
        sizes.ComputeAreaOff()
        sizes.ComputeVolumeOn()
        sizes.Update()
        v = sizes.GetOutput().GetCellData().GetArray("Volume")
        out["volumes"] = [v.GetValue(i) for i in range(v.GetNumberOfTuples())]
        out["total_volume"] = sum(out["volumes"])
        out["face_volumes"] = [
            face_volume(ds.GetCell(c), ds.GetPoints()) for c in range(ds.GetNumberOfCells())
        ]
    else:
        out["n_verts"] = ds.GetNumberOfVerts()
    return out


def collection(path):
    base = os.path.dirname(path)
    datasets = []
    for d in ET.parse(path).getroot().iter("DataSet"):
        f = os.path.join(base, d.get("file"))
        ds = read(f)
        datasets.append({
            "timestep": float(d.get("timestep")),
            "part": int(d.get("part", "0")),
            "file": d.get("file"),
            "n_points": ds.GetNumberOfPoints(),
            "n_cells": ds.GetNumberOfCells(),
        })
    return {"datasets": datasets}


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    path = sys.argv[1]
    window = capture_messages()
    out = collection(path) if path.endswith(".pvd") else summary(path)
    messages = window.GetOutput().strip()
    out["errors"] = [m for m in messages.splitlines() if m.strip()] if messages else []
    out["vtk_version"] = vtk.vtkVersion.GetVTKVersion()
    json.dump(out, sys.stdout)
    print()
    return 1 if out["errors"] else 0


if __name__ == "__main__":
    sys.exit(main())
