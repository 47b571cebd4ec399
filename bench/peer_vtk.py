#!/usr/bin/env python3
# isoterra — the VTK peer of bench_pipeline: vtkFlyingEdges3D (normals on,
# as isoterra's vertices carry them) on raw float32 volumes, driven through
# stdin so its runs interleave with isoterra's.  Debian: python3-vtk9.
#
#   peer_vtk.py NX NY NZ ISO THREADS FILE...     (x fastest, native floats)
#
# prints "ready VERSION BACKEND THREADS", then "vol K TRIANGLES POINTS" for
# every file (after one untimed warm-up Update), then answers each stdin
# line "run K" with "K WALL_MS CPU_MS TRIANGLES POINTS" (the time of one
# Update() of volume K's filter: the child's wall and CPU time, its
# threads included).  Exit status 3: VTK cannot be imported.
import sys
import time

try:
    from vtkmodules.vtkCommonCore import vtkSMPTools, vtkVersion
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
    from vtkmodules.vtkIOImage import vtkImageReader
except ImportError:
    sys.exit(3)  # bench_pipeline says "not installed"


def volume_filter(path, dims, iso):
    r = vtkImageReader()
    r.SetFileName(path)
    r.SetFileDimensionality(3)
    r.SetDataScalarTypeToFloat()
    r.SetNumberOfScalarComponents(1)
    if sys.byteorder == "little":
        r.SetDataByteOrderToLittleEndian()
    else:
        r.SetDataByteOrderToBigEndian()
    r.SetFileLowerLeft(1)  # rows in memory order, y up
    r.SetHeaderSize(0)
    r.SetDataExtent(0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    r.Update()
    img = vtkImageData()
    img.DeepCopy(r.GetOutput())  # the reader stays out of the timed runs
    fe = vtkFlyingEdges3D()
    fe.SetInputData(img)
    fe.SetValue(0, iso)
    fe.ComputeNormalsOn()
    fe.ComputeGradientsOff()
    fe.ComputeScalarsOff()
    fe.InterpolateAttributesOff()
    fe.Update()  # warm-up
    return img, fe


def main():
    if len(sys.argv) < 7:
        print("usage: peer_vtk.py NX NY NZ ISO THREADS FILE...", file=sys.stderr)
        return 2
    dims = [int(a) for a in sys.argv[1:4]]
    iso = float(sys.argv[4])
    vtkSMPTools.Initialize(int(sys.argv[5]))
    backend = vtkSMPTools.GetBackend() if hasattr(vtkSMPTools, "GetBackend") else "?"
    print("ready %s %s %d" % (vtkVersion.GetVTKVersion(), backend or "?",
                              vtkSMPTools.GetEstimatedNumberOfThreads()), flush=True)
    filters = []
    for k, path in enumerate(sys.argv[6:]):
        img, fe = volume_filter(path, dims, iso)
        filters.append((img, fe))
        out = fe.GetOutput()
        print("vol %d %d %d" % (k, out.GetNumberOfPolys(), out.GetNumberOfPoints()), flush=True)
    for line in sys.stdin:
        w = line.split()
        if len(w) != 2 or w[0] != "run" or not 0 <= int(w[1]) < len(filters):
            print("error: bad command %r" % line, flush=True)
            continue
        k = int(w[1])
        fe = filters[k][1]
        fe.Modified()
        t0, c0 = time.perf_counter(), time.process_time()
        fe.Update()
        t1, c1 = time.perf_counter(), time.process_time()
        out = fe.GetOutput()
        print("%d %.3f %.3f %d %d" % (k, (t1 - t0) * 1e3, (c1 - c0) * 1e3, out.GetNumberOfPolys(),
                                      out.GetNumberOfPoints()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
