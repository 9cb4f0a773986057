"""Opens a debris trajectory (.xmf + .h5) with ParaView's own XDMF readers and checks what they show.

    pvpython --force-offscreen-rendering check_trajectory.py DIR/run.xmf DIR/expected.json

expected.json (written by write_sample): {"times": [...], "first": FRAME, "last": FRAME} where FRAME is
{"points": N, "id": [...], "position": [[x, y, z], ...], "radius": [...], "label": [...],
"angular_velocity": [[wx, wy, wz], ...], "image": [[ix, iy, iz], ...], "type": [...], "group": [...],
"velocity": [[vx, vy, vz], ...], "force": [[fx, fy, fz], ...]} in id order: every field the writer stores. Both XDMF readers
are tried, the XDMF 2 reader (XDMFReader) and the XDMF 3 reader (Xdmf3ReaderS); each must show the same
time steps, point counts and values, bit for bit. Exits 1 with one line per problem otherwise.
Open the .xmf through a path with a directory part: ParaView resolves the .h5 relative to it.
"""
import json
import os
import sys

from paraview import servermanager, simple


def first_leaf(data):
    """The dataset itself, or the first non-empty block of a multiblock output."""
    if data is None or not data.IsA("vtkCompositeDataSet"):
        return data
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        leaf = it.GetCurrentDataObject()
        if leaf is not None and leaf.GetNumberOfPoints() > 0:
            return leaf
        it.GoToNextItem()
    return None


def frame_at(reader, time):
    """The reader's output at `time`, fetched to this process."""
    forced = simple.ForceTime(Input=reader, IgnorePipelineTime=1, ForcedTime=time)
    data = first_leaf(servermanager.Fetch(forced))
    simple.Delete(forced)
    return data


def check_frame(label, data, want, problems):
    if data is None:
        problems.append(f"{label}: the reader produced no points")
        return
    n = data.GetNumberOfPoints()
    if n != want["points"]:
        problems.append(f"{label}: {n} points, expected {want['points']}")
        return
    arrays = data.GetPointData()
    ids, radius = arrays.GetArray("id"), arrays.GetArray("radius")
    for name, array in (("id", ids), ("radius", radius)):
        if array is None:
            have = [arrays.GetArrayName(i) for i in range(arrays.GetNumberOfArrays())]
            problems.append(f"{label}: no point array '{name}' (have {have})")
    if ids is None or radius is None:
        return
    for i in range(n):
        got_id = ids.GetTuple1(i)
        if got_id != want["id"][i]:
            problems.append(f"{label}: point {i} has id {got_id}, expected {want['id'][i]}")
        got_xyz = list(data.GetPoint(i))
        if got_xyz != want["position"][i]:
            problems.append(f"{label}: point {i} (id {want['id'][i]}) at {got_xyz}, expected {want['position'][i]}")
        if radius.GetTuple1(i) != want["radius"][i]:
            problems.append(f"{label}: point {i} radius {radius.GetTuple1(i)!r}, expected {want['radius'][i]!r}")
    # Every other column the writer stores, exact: scalars (label, type, group) and 3-vectors.
    for name in ("label", "type", "group", "velocity", "force", "angular_velocity", "image"):
        array = arrays.GetArray(name)
        if array is None:
            problems.append(f"{label}: no point array '{name}'")
            continue
        scalar = name in ("label", "type", "group")
        for i in range(n):
            got = array.GetTuple1(i) if scalar else list(array.GetTuple3(i))
            if got != want[name][i]:
                problems.append(f"{label}: point {i} (id {want['id'][i]}) {name} {got!r}, expected {want[name][i]!r}")


def check_reader(name, make, path, want):
    problems = []
    try:
        reader = make(path)
        reader.UpdatePipelineInformation()
    except Exception as e:  # a reader that cannot even open the file
        return [f"cannot open {path}: {e}"]
    times = list(reader.TimestepValues)
    if times != want["times"]:
        problems.append(f"time steps {times}, expected {want['times']}")
    if times:
        check_frame(f"first time step ({times[0]})", frame_at(reader, times[0]), want["first"], problems)
        check_frame(f"last time step ({times[-1]})", frame_at(reader, times[-1]), want["last"], problems)
    simple.Delete(reader)
    return problems


READERS = {
    "XDMFReader (XDMF 2)": lambda path: simple.XDMFReader(FileNames=[path]),
    "Xdmf3ReaderS (XDMF 3)": lambda path: simple.Xdmf3ReaderS(FileName=[path]),
}


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    path, expected = argv[1], argv[2]
    if not os.path.dirname(path):
        path = os.path.join(".", path)  # ParaView needs the directory part to find the .h5
    if not os.path.isfile(path):
        print(f"check_trajectory: no file {path}", file=sys.stderr)
        return 1
    with open(expected) as f:
        want = json.load(f)
    failed = 0
    for name, make in READERS.items():
        problems = check_reader(name, make, path, want)
        if problems:
            failed += 1
            for p in problems:
                print(f"FAIL {name}: {p}")
        else:
            print(f"ok   {name}: {len(want['times'])} time steps, {want['first']['points']} then "
                  f"{want['last']['points']} points, positions, ids, radii, labels, types, groups, velocities, forces, angular velocities and images exact")
    print(f"{simple.GetParaViewSourceVersion()}: {len(READERS) - failed} of {len(READERS)} XDMF readers "
          f"show {path} correctly")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
