#!/usr/bin/env python3
"""Writes the fuzz corpus of bad inputs for issue 10 (no input may crash anything).

    python3 make_corpus.py OUTPUT_DIR

Plain Python 3, standard library only; the output is deterministic (same bytes on every
run). OUTPUT_DIR receives one file per case, named ``<class>__<case>.<ext>`` so the class
can be read from the name, a few helper files whose names start with ``_`` (valid inputs
that a case pairs with a bad one), and ``cases.json``, a list of

    {"file": "truncated__vti_raw_half.vti",   # the case's file, relative to OUTPUT_DIR
     "class": "truncated",
     "cli_args": [...] or null,               # volillum-render arguments (paths relative
                                              # to OUTPUT_DIR; the runner adds --output
                                              # first, so a config's "output" wins)
     "filters": [...],                        # paraview.simple filter names for pvpython
     "properties": {filter: {prop: value}},   # optional: set before the first update
     "then": {filter: {prop: value}},         # optional: set after it, then update again
     "prepare": {"scalar_tuples": 20},        # optional: pvpython changes the data in
                                              # memory first, as a Programmable Filter
                                              # could: 20 more scalar tuples than points
                                              # (negative: fewer), or "spacing"/"origin"
                                              # [x, y, z] (NaN, Infinity): things no file
                                              # can carry, since the readers check them
     "expect": {"cli": "error", ...},         # optional: targets that must refuse the
                                              # input (an exit-0 run is then reported)
     "note": "..."}                           # what the case is about

Non-finite numbers in "properties"/"then" are written as the strings "NaN", "Infinity"
and "-Infinity" so that cases.json stays strict JSON (the worker converts them back).

Classes: control (valid inputs: the harness must report them ok), truncated, absurd_size,
absurd_spacing, header (garbled NRRD and MetaImage header fields, issue 43), scalar_type,
config, cli_args, grid, surface, filter_props.
Volumes are tiny (16^3 to 24^3) and images 64x64 so that a full run takes well under two
minutes. Run it through run_fuzz.py, which generates the corpus itself when needed.
"""
import base64
import json
import math
import os
import random
import struct
import sys

NAN = float("nan")
INF = float("inf")

IMAGE_FILTERS = ["RayMarchedIllumination", "MultiLightIlluminationVolume",
                 "FilteredVolumetricShadows", "AdaptiveTetrahedralMeshCGAL"]
GRID_FILTERS = ["UnstructuredGridIllumination"]
SURFACE_FILTERS = ["TetrahedralizeSurfaceTetGen"]

# The CLI renders 64x64 images: small and fast.
SMALL = ["--size", "64", "64"]
# Valid settings paired with every grid case: a small level-0 grid keeps the CLI fast.
GRID_CONFIG = "_grid_fast.json"
# The valid phantom paired with every bad config.
PHANTOM = ["--phantom", "spheres", "--dims", "24"]


def num(x):
    """A number as VTK, MetaIO and NRRD headers write it ('nan', 'inf', '1e+30', '3')."""
    if isinstance(x, float) and x.is_integer() and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


def nums(values):
    return " ".join(num(v) for v in values)


# --------------------------------------------------------------------------------------
# Voxel data
# --------------------------------------------------------------------------------------
# struct codes, VTK XML type names, MetaIO element types, NRRD types, legacy VTK types.
TYPES = {
    "uint8": ("B", "UInt8", "MET_UCHAR", "uchar", "unsigned_char"),
    "int8": ("b", "Int8", "MET_CHAR", "signed char", "char"),
    "int16": ("h", "Int16", "MET_SHORT", "short", "short"),
    "uint64": ("Q", "UInt64", "MET_ULONG_LONG", "uint64", "unsigned_long"),
    "float32": ("f", "Float32", "MET_FLOAT", "float", "float"),
    "float64": ("d", "Float64", "MET_DOUBLE", "double", "double"),
}


def sphere_values(dims, lo=0.0, hi=255.0):
    """A soft ball in the middle of the image (x fastest), from lo outside to hi inside."""
    nx, ny, nz = dims
    cx, cy, cz = (nx - 1) / 2.0, (ny - 1) / 2.0, (nz - 1) / 2.0
    radius = max(1.0, 0.4 * max(dims))
    out = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                r = math.sqrt((i - cx) ** 2 + (j - cy) ** 2 + (k - cz) ** 2)
                t = min(1.0, max(0.0, 1.5 - r / radius))
                out.append(lo + (hi - lo) * t)
    return out


def pack(kind, values):
    code = TYPES[kind][0]
    if code in "fd":
        return struct.pack("<%d%s" % (len(values), code), *values)
    return struct.pack("<%d%s" % (len(values), code), *[int(v) for v in values])


# --------------------------------------------------------------------------------------
# Writers (bytes)
# --------------------------------------------------------------------------------------
def vti_bytes(dims=(16, 16, 16), spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0),
              arrays=None, whole_extent=None, direction=None, block_sizes=None):
    """XML ImageData, header_type UInt64, every array in one raw <AppendedData> block.

    arrays: list of (name, kind, components, payload bytes); None: one uint8 ball named
    'density'. whole_extent overrides the extent written (the data stays as given).
    block_sizes overrides the UInt64 byte counts written before each array's data.
    """
    if arrays is None:
        arrays = [("density", "uint8", 1, pack("uint8", sphere_values(dims)))]
    extent = whole_extent or (0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    direction_attr = ' Direction="%s"' % nums(direction) if direction is not None else ""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" '
             'header_type="UInt64">',
             '  <ImageData WholeExtent="%s" Origin="%s" Spacing="%s"%s>'
             % (nums(extent), nums(origin), nums(spacing), direction_attr),
             '    <Piece Extent="%s">' % nums(extent)]
    scalars = ' Scalars="%s"' % arrays[0][0] if arrays else ""
    lines.append("      <PointData%s>" % scalars)
    offset = 0
    blocks = []
    for index, (name, kind, components, payload) in enumerate(arrays):
        lines.append('        <DataArray type="%s" Name="%s" NumberOfComponents="%d" '
                     'format="appended" offset="%d"/>' % (TYPES[kind][1], name, components, offset))
        size = block_sizes[index] if block_sizes else len(payload)
        block = struct.pack("<Q", size) + payload
        blocks.append(block)
        offset += len(block)
    lines += ["      </PointData>", "      <CellData>", "      </CellData>",
              "    </Piece>", "  </ImageData>", '  <AppendedData encoding="raw">', "   _"]
    head = ("\n".join(lines)).encode("ascii")
    return head + b"".join(blocks) + b"\n  </AppendedData>\n</VTKFile>\n"


def mha_bytes(dims=(16, 16, 16), spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0),
              kind="uint8", channels=1, payload=None, header_dims=None):
    """MetaImage with the data in the same file (ElementDataFile = LOCAL)."""
    if payload is None:
        payload = pack(kind, sphere_values(dims) * channels)
    hd = header_dims or dims
    header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\n"
              "BinaryDataByteOrderMSB = False\nCompressedData = False\n"
              "TransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = %s\nCenterOfRotation = 0 0 0\n"
              "ElementSpacing = %s\nDimSize = %s\nElementNumberOfChannels = %d\n"
              "ElementType = %s\nElementDataFile = LOCAL\n"
              % (nums(origin), nums(spacing), " ".join(str(d) for d in hd), channels,
                 TYPES[kind][2]))
    return header.encode("ascii") + payload


def nrrd_bytes(dims=(16, 16, 16), spacing=(1.0, 1.0, 1.0), kind="uint8", payload=None,
               header_dims=None):
    """NRRD with raw little-endian data after the blank line."""
    if payload is None:
        payload = pack(kind, sphere_values(dims))
    hd = header_dims or dims
    header = ("NRRD0004\n# fuzz case\ntype: %s\ndimension: 3\nsizes: %s\nspacings: %s\n"
              "encoding: raw\nendian: little\n\n"
              % (TYPES[kind][3], " ".join(str(d) for d in hd), nums(spacing)))
    return header.encode("ascii") + payload


# Header fields of a valid 16^3 uchar NRRD and MetaImage, one per line, for the header cases
# to garble (the MetaImage's ElementDataFile must stay last).
NRRD_FIELDS = ["type: uchar", "dimension: 3", "sizes: 16 16 16", "spacings: 1 1 1",
               "encoding: raw", "endian: little"]
MHA_FIELDS = ["ObjectType = Image", "NDims = 3", "BinaryData = True",
              "BinaryDataByteOrderMSB = False", "CompressedData = False",
              "ElementSpacing = 1 1 1", "DimSize = 16 16 16", "ElementNumberOfChannels = 1",
              "ElementType = MET_UCHAR", "ElementDataFile = LOCAL"]


def edit_fields(fields, separator, changes):
    """fields with changes ({name: value, or None to drop}) applied; a name not among the
    fields is added before the last field. Values are text with any bytes (latin-1)."""
    out, done = [], set()
    for line in fields:
        name = line.split(separator)[0].strip()
        if name in changes:
            done.add(name)
            if changes[name] is not None:
                out.append("%s%s %s" % (name, separator, changes[name]))
        else:
            out.append(line)
    extra = ["%s%s %s" % (k, separator, v) for k, v in changes.items()
             if k not in done and v is not None]
    return out[:-1] + extra + out[-1:]


def nrrd_header_bytes(lines, payload=b"", detached=False, magic="NRRD0004"):
    """A NRRD made of the given header lines; attached (blank line, then payload) or a
    detached header (.nhdr, no blank line)."""
    text = magic + "\n" + "\n".join(lines) + ("\n" if detached else "\n\n")
    return text.encode("latin-1") + payload


def mha_header_bytes(lines, payload=b""):
    return ("\n".join(lines) + "\n").encode("latin-1") + payload


def legacy_vtk_bytes(dims=(8, 8, 8), kind="uint8", values=None, header_dims=None,
                     spacing=(1.0, 1.0, 1.0)):
    """Legacy ASCII STRUCTURED_POINTS."""
    if values is None:
        values = sphere_values(dims, 0, 100)
    hd = header_dims or dims
    n = hd[0] * hd[1] * hd[2]
    text = ("# vtk DataFile Version 3.0\nfuzz case\nASCII\nDATASET STRUCTURED_POINTS\n"
            "DIMENSIONS %d %d %d\nSPACING %s\nORIGIN 0 0 0\nPOINT_DATA %d\n"
            "SCALARS density %s 1\nLOOKUP_TABLE default\n" % (hd[0], hd[1], hd[2],
                                                             nums(spacing), n, TYPES[kind][4]))
    body = "\n".join(" ".join(num(float(int(v))) for v in values[i:i + 16])
                     for i in range(0, len(values), 16))
    return (text + body + "\n").encode("ascii")


def _xml_array(name, vtk_type, components, values):
    """One DataArray: ASCII, or inline base64 (UInt64 header) when a value is not finite,
    since VTK's ASCII parser cannot read 'nan' or 'inf'."""
    comp = ' NumberOfComponents="%d"' % components if components != 1 else ""
    label = ' Name="%s"' % name if name else ""
    floats = vtk_type.startswith("Float")
    if floats and not all(math.isfinite(v) for v in values):
        payload = struct.pack("<%d%s" % (len(values), "f" if vtk_type == "Float32" else "d"),
                              *values)
        data = base64.b64encode(struct.pack("<Q", len(payload)) + payload).decode("ascii")
        return ('<DataArray type="%s"%s%s format="binary">%s</DataArray>'
                % (vtk_type, label, comp, data))
    text = " ".join(num(float(v)) if floats else str(int(v)) for v in values)
    return '<DataArray type="%s"%s%s format="ascii">%s</DataArray>' % (vtk_type, label, comp, text)


def vtu_bytes(points, cells, point_arrays=(), cell_arrays=()):
    """ASCII XML UnstructuredGrid. cells: list of (vtk cell type, [point ids]).
    point_arrays / cell_arrays: (name, components, values); the first point array is the
    active scalars."""
    flat = [c for p in points for c in p]
    conn = [i for _, ids in cells for i in ids]
    offsets, total = [], 0
    for _, ids in cells:
        total += len(ids)
        offsets.append(total)
    types = [t for t, _ in cells]
    scalars = ' Scalars="%s"' % point_arrays[0][0] if point_arrays else ""
    out = ['<?xml version="1.0"?>',
           '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
           'header_type="UInt64">', "  <UnstructuredGrid>",
           '    <Piece NumberOfPoints="%d" NumberOfCells="%d">' % (len(points), len(cells)),
           "      <PointData%s>" % scalars]
    out += ["        " + _xml_array(n, "Float32", c, v) for n, c, v in point_arrays]
    out += ["      </PointData>", "      <CellData>"]
    out += ["        " + _xml_array(n, "Float32", c, v) for n, c, v in cell_arrays]
    out += ["      </CellData>", "      <Points>",
            "        " + _xml_array("", "Float64", 3, flat), "      </Points>",
            "      <Cells>",
            "        " + _xml_array("connectivity", "Int64", 1, conn),
            "        " + _xml_array("offsets", "Int64", 1, offsets),
            "        " + _xml_array("types", "UInt8", 1, types),
            "      </Cells>", "    </Piece>", "  </UnstructuredGrid>", "</VTKFile>", ""]
    return "\n".join(out).encode("ascii")


def vtp_bytes(points, polys=(), lines=()):
    """ASCII XML PolyData with polygons (and optionally lines)."""
    flat = [c for p in points for c in p]

    def section(tag, cells):
        if not cells:
            return []
        conn = [i for ids in cells for i in ids]
        offsets, total = [], 0
        for ids in cells:
            total += len(ids)
            offsets.append(total)
        return ["      <%s>" % tag,
                "        " + _xml_array("connectivity", "Int64", 1, conn),
                "        " + _xml_array("offsets", "Int64", 1, offsets),
                "      </%s>" % tag]

    out = ['<?xml version="1.0"?>',
           '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
           'header_type="UInt64">', "  <PolyData>",
           '    <Piece NumberOfPoints="%d" NumberOfVerts="0" NumberOfLines="%d" '
           'NumberOfStrips="0" NumberOfPolys="%d">' % (len(points), len(lines), len(polys)),
           "      <Points>", "        " + _xml_array("", "Float64", 3, flat), "      </Points>"]
    out += section("Lines", list(lines)) + section("Polys", list(polys))
    out += ["    </Piece>", "  </PolyData>", "</VTKFile>", ""]
    return "\n".join(out).encode("ascii")


# --------------------------------------------------------------------------------------
# Geometry
# --------------------------------------------------------------------------------------
VTK_TRIANGLE, VTK_POLYGON, VTK_TETRA, VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID = 5, 7, 10, 12, 13, 14


def lattice(n=4, scale=1.0, flat=False):
    """n^3 points of a unit cube lattice (x fastest) and the index function."""
    pts = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                pts.append((i * scale / (n - 1), j * scale / (n - 1),
                            0.0 if flat else k * scale / (n - 1)))
    return pts, (lambda i, j, k: i + n * (j + n * k))


def cubes(n):
    for k in range(n - 1):
        for j in range(n - 1):
            for i in range(n - 1):
                yield i, j, k


def tet_grid(n=4, flat=False):
    """Each lattice cube split into 6 tetrahedra around its main diagonal."""
    pts, idx = lattice(n, flat=flat)
    cells = []
    for i, j, k in cubes(n):
        v = [idx(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)) for c in range(8)]
        for a, b in ((1, 3), (3, 2), (2, 6), (6, 4), (4, 5), (5, 1)):
            cells.append((VTK_TETRA, [v[0], v[a], v[b], v[7]]))
    return pts, cells


def hex_grid(n=4):
    pts, idx = lattice(n)
    cells = []
    for i, j, k in cubes(n):
        cells.append((VTK_HEXAHEDRON, [idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k),
                                       idx(i, j + 1, k), idx(i, j, k + 1), idx(i + 1, j, k + 1),
                                       idx(i + 1, j + 1, k + 1), idx(i, j + 1, k + 1)]))
    return pts, cells


def wedge_grid(n=4):
    pts, idx = lattice(n)
    cells = []
    for i, j, k in cubes(n):
        a, b, c, d = idx(i, j, k), idx(i + 1, j, k), idx(i + 1, j + 1, k), idx(i, j + 1, k)
        e, f, g, h = (idx(i, j, k + 1), idx(i + 1, j, k + 1), idx(i + 1, j + 1, k + 1),
                      idx(i, j + 1, k + 1))
        cells.append((VTK_WEDGE, [a, b, c, e, f, g]))
        cells.append((VTK_WEDGE, [a, c, d, e, g, h]))
    return pts, cells


def pyramid_grid(n=3):
    """Each cube as six pyramids whose apex is an extra point at the cube's centre."""
    pts, idx = lattice(n)
    pts = list(pts)
    cells = []
    for i, j, k in cubes(n):
        v = {(a, b, c): idx(i + a, j + b, k + c) for a in (0, 1) for b in (0, 1) for c in (0, 1)}
        centre = len(pts)
        pts.append(((i + 0.5) / (n - 1), (j + 0.5) / (n - 1), (k + 0.5) / (n - 1)))
        faces = [[(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)], [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],
                 [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)],
                 [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)], [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)]]
        for face in faces:
            cells.append((VTK_PYRAMID, [v[c] for c in face] + [centre]))
    return pts, cells


def ball_scalars(points):
    """A density falling off from the centre of the unit cube."""
    return [max(0.0, 1.0 - 1.6 * math.sqrt((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2))
            if all(math.isfinite(c) for c in (x, y, z)) else 0.5 for x, y, z in points]


CUBE_POINTS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
# Twelve outward-facing triangles of the unit cube.
CUBE_TRIANGLES = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [2, 3, 7], [2, 7, 6], [1, 2, 6], [1, 6, 5], [0, 4, 7], [0, 7, 3]]


def cube_points(scale=1.0, shift=(0.0, 0.0, 0.0)):
    return [tuple(float(c) * scale + s for c, s in zip(p, shift)) for p in CUBE_POINTS]


def flip_bytes(data, start, end, count, rng):
    """XORs count bytes at seeded random positions of data[start:end] with 0xFF."""
    out = bytearray(data)
    for _ in range(count):
        pos = rng.randrange(start, end)
        out[pos] ^= 0xFF
    return bytes(out)


# --------------------------------------------------------------------------------------
# The corpus
# --------------------------------------------------------------------------------------
class Corpus:
    def __init__(self, root):
        self.root = root
        self.cases = []

    def helper(self, name, data):
        with open(os.path.join(self.root, name), "wb") as f:
            f.write(data)

    def add(self, klass, case, ext, data, cli_args=None, filters=(), expect=None,
            properties=None, then=None, note="", prepare=None):
        """Writes <class>__<case>.<ext>. cli_args: a list, or 'auto' for the default
        arguments of the file's kind (with the file name at the end)."""
        name = "%s__%s.%s" % (klass, case, ext)
        with open(os.path.join(self.root, name), "wb") as f:
            f.write(data)
        if cli_args == "auto":
            if ext in ("vtu",):
                cli_args = SMALL + ["--config", GRID_CONFIG, name]
            elif ext == "json":
                cli_args = SMALL + ["--config", name] + PHANTOM
            else:
                cli_args = SMALL + [name]
        entry = {"file": name, "class": klass, "cli_args": cli_args, "filters": list(filters)}
        if properties:
            entry["properties"] = _strict(properties)
        if then:
            entry["then"] = _strict(then)
        if prepare:
            entry["prepare"] = prepare
        if expect:
            entry["expect"] = expect
        if note:
            entry["note"] = note
        self.cases.append(entry)


def _strict(value):
    """Non-finite floats as the strings NaN / Infinity / -Infinity (strict JSON)."""
    if isinstance(value, dict):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return "NaN" if value != value else ("Infinity" if value > 0 else "-Infinity")
    return value


def image_case(corpus, klass, case, ext, data, expect_cli=None, note=""):
    expect = {"cli": expect_cli} if expect_cli else None
    corpus.add(klass, case, ext, data, cli_args="auto", filters=IMAGE_FILTERS,
               expect=expect, note=note)


def build(corpus):
    rng = random.Random(10)
    dims = (16, 16, 16)
    valid_vti = vti_bytes(dims)
    valid_mha = mha_bytes(dims)
    valid_nrrd = nrrd_bytes(dims)
    valid_legacy = legacy_vtk_bytes()
    tets_pts, tets = tet_grid()
    valid_vtu = vtu_bytes(tets_pts, tets, [("density", 1, ball_scalars(tets_pts))])
    valid_vtp = vtp_bytes(cube_points(), CUBE_TRIANGLES)

    corpus.helper(GRID_CONFIG, json.dumps({"level0_resolution": 16}, indent=1).encode())

    # ---- control: valid inputs; the harness must report them "ok" -------------------
    image_case(corpus, "control", "ball16", "vti", valid_vti, note="valid 16^3 uchar ball")
    image_case(corpus, "control", "ball16", "mha", valid_mha, note="valid MetaImage")
    corpus.add("control", "tets", "vtu", valid_vtu, cli_args="auto", filters=GRID_FILTERS,
               note="valid 162-tetrahedron grid")
    corpus.add("control", "cube", "vtp", valid_vtp, filters=SURFACE_FILTERS,
               note="valid closed cube surface")
    corpus.add("control", "settings", "json",
               json.dumps({"method": "filtered", "image_size": [64, 64],
                           "lights": [{"type": "point", "position": [-0.5, 1.5, 1.5],
                                       "relative": True}]}, indent=1).encode(),
               cli_args="auto", note="valid settings")

    # ---- truncated and corrupted files ---------------------------------------------
    T = "truncated"
    data_start = valid_vti.index(b"   _") + 4
    image_case(corpus, T, "vti_raw_half", "vti", valid_vti[:len(valid_vti) // 2], "error",
               "appended raw data cut in half")
    image_case(corpus, T, "vti_cut_in_xml", "vti", valid_vti[:data_start // 2], "error",
               "cut inside the XML header")
    image_case(corpus, T, "vti_header_flipped", "vti",
               flip_bytes(valid_vti, 0, data_start, 12, rng), "error",
               "12 bytes of the XML header XOR 0xFF")
    image_case(corpus, T, "vti_data_flipped", "vti",
               flip_bytes(valid_vti, data_start + 8, len(valid_vti) - 30, 200, rng), None,
               "200 voxel bytes XOR 0xFF (a valid file with odd values)")
    image_case(corpus, T, "vti_block_size_huge", "vti",
               vti_bytes(dims, block_sizes=[2 ** 63 + 5]), "error",
               "the UInt64 byte count of the block says 2^63+5")
    image_case(corpus, T, "vti_block_size_short", "vti",
               vti_bytes(dims, block_sizes=[100]), "error",
               "the UInt64 byte count says 100 bytes for 4096 voxels")
    image_case(corpus, T, "mha_header_only", "mha", mha_bytes(dims, payload=b""), "error",
               "MetaImage header without data")
    image_case(corpus, T, "mha_half", "mha", valid_mha[:len(valid_mha) // 2], "error",
               "MetaImage cut in half")
    image_case(corpus, T, "mha_header_garbage", "mha",
               flip_bytes(valid_mha, 0, valid_mha.index(b"ElementDataFile"), 10, rng), "error",
               "10 header bytes XOR 0xFF")
    image_case(corpus, T, "nrrd_half", "nrrd", valid_nrrd[:len(valid_nrrd) // 2], "error",
               "NRRD cut in half")
    image_case(corpus, T, "nrrd_header_only", "nrrd", nrrd_bytes(dims, payload=b""), "error",
               "NRRD header without data")
    image_case(corpus, T, "nrrd_header_garbage", "nrrd",
               flip_bytes(valid_nrrd, 0, valid_nrrd.index(b"\n\n"), 8, rng), "error",
               "8 header bytes XOR 0xFF")
    image_case(corpus, T, "legacy_vtk_half", "vtk", valid_legacy[:len(valid_legacy) // 2],
               "error", "legacy ASCII structured points cut in half")
    corpus.add(T, "vtu_half", "vtu", valid_vtu[:len(valid_vtu) // 2], cli_args="auto",
               filters=GRID_FILTERS, expect={"cli": "error"}, note="ASCII grid cut in half")
    corpus.add(T, "vtp_half", "vtp", valid_vtp[:len(valid_vtp) // 2], filters=SURFACE_FILTERS,
               note="surface cut in half")
    for ext in ("vti", "mha", "nrrd"):
        image_case(corpus, T, "empty_" + ext, ext, b"", "error", "empty file")
    corpus.add(T, "empty_vtu", "vtu", b"", cli_args="auto", filters=GRID_FILTERS,
               expect={"cli": "error"}, note="empty file")
    corpus.add(T, "empty_vtp", "vtp", b"", filters=SURFACE_FILTERS, note="empty file")
    corpus.add(T, "empty_json", "json", b"", cli_args="auto", expect={"cli": "error"},
               note="empty settings file")
    garbage = bytes(rng.randrange(256) for _ in range(3000))
    image_case(corpus, T, "random_bytes_vti", "vti", garbage, "error", "3000 random bytes")

    # ---- absurd sizes ----------------------------------------------------------------
    A = "absurd_size"
    little = pack("uint8", sphere_values((8, 8, 8)))
    image_case(corpus, A, "vti_extent_100000", "vti",
               vti_bytes((8, 8, 8), whole_extent=(0, 99999) * 3), "error",
               "WholeExtent 100000^3 with 512 bytes of data")
    image_case(corpus, A, "mha_dimsize_100000", "mha",
               mha_bytes(header_dims=(100000, 100000, 100000), payload=little), "error",
               "DimSize 100000^3 with 512 bytes of data")
    image_case(corpus, A, "nrrd_sizes_100000", "nrrd",
               nrrd_bytes(header_dims=(100000, 100000, 100000), payload=little), "error",
               "sizes 100000^3 with 512 bytes of data")
    image_case(corpus, A, "mha_2e9_uchar", "mha",
               mha_bytes(header_dims=(1260, 1260, 1260), payload=little), "error",
               "2.0e9 uchar voxels claimed, 512 bytes given")
    image_case(corpus, A, "mha_dimsize_zero", "mha",
               mha_bytes(header_dims=(16, 0, 16), payload=b""), "error", "DimSize 16 0 16")
    image_case(corpus, A, "mha_dimsize_negative", "mha",
               mha_bytes(header_dims=(16, -16, 16), payload=little), "error", "DimSize 16 -16 16")
    image_case(corpus, A, "vti_extent_inverted", "vti",
               vti_bytes((8, 8, 8), whole_extent=(7, 0, 0, 7, 0, 7)), "error",
               "WholeExtent 7 0 0 7 0 7 (empty)")
    image_case(corpus, A, "legacy_vtk_dims_100000", "vtk",
               legacy_vtk_bytes(header_dims=(100000, 100000, 100000)), "error",
               "DIMENSIONS 100000^3 with 512 values")
    image_case(corpus, A, "vti_one_voxel", "vti", vti_bytes((1, 1, 1)), None, "1x1x1 image")
    image_case(corpus, A, "vti_2d_z1", "vti", vti_bytes((24, 24, 1)), None,
               "24x24x1 image (2D)")
    image_case(corpus, A, "mha_2d_y1", "mha", mha_bytes((24, 1, 24)), None, "24x1x24 image (2D)")
    image_case(corpus, A, "vti_line_x", "vti", vti_bytes((32, 1, 1)), None, "32x1x1 image (1D)")

    # ---- absurd spacings and origins -------------------------------------------------
    S = "absurd_spacing"
    for case, spacing in (("spacing_1e30", (1e30,) * 3), ("spacing_1e-30", (1e-30,) * 3),
                          ("spacing_zero", (0.0,) * 3), ("spacing_negative", (-1.0, 1.0, -2.0)),
                          ("spacing_nan", (NAN,) * 3), ("spacing_inf", (INF, 1.0, 1.0)),
                          ("spacing_mixed_1e-30_1e30", (1e-30, 1.0, 1e30))):
        image_case(corpus, S, "vti_" + case, "vti", vti_bytes(dims, spacing=spacing), None,
                   "Spacing %s" % nums(spacing))
    image_case(corpus, S, "vti_origin_1e300", "vti", vti_bytes(dims, origin=(1e300,) * 3), None,
               "Origin 1e300 (finite bounds near the largest double)")
    image_case(corpus, S, "vti_origin_nan", "vti", vti_bytes(dims, origin=(NAN, 0.0, 0.0)), None,
               "Origin nan 0 0")
    image_case(corpus, S, "vti_direction_zero", "vti", vti_bytes(dims, direction=(0.0,) * 9),
               None, "Direction matrix all zeros")
    image_case(corpus, S, "mha_spacing_1e30", "mha", mha_bytes(dims, spacing=(1e30,) * 3), None,
               "ElementSpacing 1e30")
    image_case(corpus, S, "mha_spacing_nan", "mha", mha_bytes(dims, spacing=(NAN,) * 3), None,
               "ElementSpacing nan nan nan (MetaIO parses it; VTK XML does not)")
    for case, key, value in (("spacing_nan_in_memory", "spacing", [NAN, NAN, NAN]),
                             ("spacing_inf_in_memory", "spacing", [INF, 1.0, 1.0]),
                             ("origin_nan_in_memory", "origin", [NAN, 0.0, 0.0]),
                             ("origin_inf_in_memory", "origin", [0.0, -INF, 0.0])):
        corpus.add(S, case, "vti", valid_vti, filters=IMAGE_FILTERS,
                   prepare={key: _strict(value)},
                   note="valid file; in memory the image's %s becomes %s" % (key, nums(value)))
    image_case(corpus, S, "nrrd_spacing_zero", "nrrd", nrrd_bytes(dims, spacing=(0.0,) * 3),
               None, "spacings 0 0 0")

    # ---- garbled NRRD and MetaImage headers (issue 43) ---------------------------------
    # volillum-render checks these headers before vtkNrrdReader / MetaIO see them (they
    # crashed, hung or read garbage on several): every case must be one clean refusal. The
    # CLI only: ParaView's own readers in pvpython are not the project's code.
    H = "header"
    ball = pack("uint8", sphere_values(dims))
    corpus.helper("_ball16.raw", ball)
    for k in range(4):
        corpus.helper("_slice%02d.raw" % k, ball[256 * k:256 * (k + 1)])

    def header_case(case, ext, data, note, expect_cli="error", klass=H):
        corpus.add(klass, case, ext, data, cli_args="auto",
                   expect={"cli": expect_cli} if expect_cli else None, note=note)

    def nrrd(case, changes, note, payload=ball, **kw):
        header_case(case, "nrrd", nrrd_header_bytes(edit_fields(NRRD_FIELDS, ":", changes),
                                                    payload, **kw), note)

    def nhdr(case, changes, note):
        header_case(case, "nhdr", nrrd_header_bytes(edit_fields(NRRD_FIELDS, ":", changes),
                                                    detached=True), note)

    def mha(case, changes, note, payload=ball):
        header_case(case, "mha", mha_header_bytes(edit_fields(MHA_FIELDS, " =", changes),
                                                  payload), note)

    header_case("ball16", "nrrd", nrrd_header_bytes(NRRD_FIELDS, ball), "valid NRRD",
                expect_cli=None, klass="control")
    header_case("ball16_detached", "nhdr",
                nrrd_header_bytes(NRRD_FIELDS + ["data file: _ball16.raw"], detached=True),
                "valid detached NRRD header", expect_cli=None, klass="control")
    header_case("ball16_slices", "nhdr",
                nrrd_header_bytes(edit_fields(NRRD_FIELDS, ":", {"sizes": "16 16 4"}) +
                                  ["data file: _slice%02d.raw 0 3 1"], detached=True),
                "valid detached NRRD header, one file per slice", expect_cli=None,
                klass="control")
    nrrd("nrrd_type_garbled", {"type": "floa\x13"}, "type: floa\\x13 (one garbled byte)",
         payload=pack("float32", sphere_values(dims)))
    nrrd("nrrd_type_unknown", {"type": "quad"}, "type: quad")
    nrrd("nrrd_type_block", {"type": "block"}, "type: block (not read by vtkNrrdReader)")
    nrrd("nrrd_type_missing", {"type": None}, "no type field")
    nrrd("nrrd_sizes_negative", {"sizes": "16 -16 16"}, "sizes: 16 -16 16")
    nrrd("nrrd_sizes_zero", {"sizes": "16 16 0"}, "sizes: 16 16 0")
    nrrd("nrrd_sizes_huge", {"sizes": "2000000000 2000000000 2000000000"}, "sizes: 2e9 each")
    nrrd("nrrd_sizes_product_huge", {"sizes": "500000 500000 500000"},
         "sizes: 500000^3 (each sane, the product absurd)")
    nrrd("nrrd_sizes_garbled", {"sizes": "16 1\x136 16"}, "sizes: 16 1\\x136 16")
    nrrd("nrrd_sizes_missing", {"sizes": None}, "no sizes field")
    header_case("nrrd_sizes_before_dimension", "nrrd",
                nrrd_header_bytes(["type: uchar", "sizes: 16 16 16", "dimension: 3",
                                   "encoding: raw"], ball), "sizes before dimension")
    nrrd("nrrd_dimension_mismatch", {"dimension": "2"}, "dimension: 2 with 3 sizes")
    nrrd("nrrd_dimension_zero", {"dimension": "0"}, "dimension: 0")
    nrrd("nrrd_dimension_negative", {"dimension": "-3"}, "dimension: -3")
    nrrd("nrrd_dimension_huge", {"dimension": "2000000000"}, "dimension: 2e9")
    nrrd("nrrd_dimension_garbled", {"dimension": "3\x13"}, "dimension: 3\\x13")
    nrrd("nrrd_one_axis", {"dimension": "1", "sizes": "32", "spacings": "1"},
         "a 1D image (32 samples)", payload=ball[:32])
    nrrd("nrrd_vector_only_axis", {"dimension": "2", "sizes": "3 32", "spacings": "nan 1"},
         "a vector axis of 3 and one spatial axis", payload=ball[:96])
    header_case("nrrd_space_then_four_sizes", "nrrd",
                nrrd_header_bytes(["type: uchar", "dimension: 4", "space: right-anterior-superior",
                                   "sizes: 3 16 16 16", "encoding: raw"], ball * 3),
                "4 sizes after a 'space' field (vtkNrrdReader then reads only 3)")
    nrrd("nrrd_encoding_unknown", {"encoding": "bzip2"}, "encoding: bzip2")
    nrrd("nrrd_encoding_garbled", {"encoding": "r\x13w"}, "encoding: r\\x13w")
    nrrd("nrrd_encoding_missing", {"encoding": None}, "no encoding field")
    nrrd("nrrd_endian_garbled", {"endian": "litt\xecle"}, "endian: litt\\xecle")
    nrrd("nrrd_field_name_garbled", {"type": None, "typ\x8be": "uchar"},
         "field name typ\\x8be")
    nrrd("nrrd_empty_value", {"space origin": ""}, "space origin: (no value)")
    header_case("nrrd_line_without_colon", "nrrd",
                nrrd_header_bytes(NRRD_FIELDS + ["sizes 16 16 16"], ball),
                "a line that is not 'field: value'")
    nrrd("nrrd_magic_garbled", {}, "first line NRRD00\\xcf4", magic="NRRD00\xcf4")
    nrrd("nrrd_data_file_empty", {"data file": ""}, "data file: (no value)")
    nrrd("nrrd_data_file_pattern_s", {"data file": "_slice%s.raw 0 3 1"},
         "data file pattern with %s")
    nrrd("nrrd_data_file_step_zero", {"data file": "_slice%02d.raw 0 3 0"},
         "data file pattern with step 0 (vtkNrrdReader loops forever)")
    nrrd("nrrd_data_file_count", {"data file": "_slice%02d.raw 0 3 1"},
         "4 data files for 16 slices")
    nhdr("nhdr_data_file_missing", {}, "detached header without a data file field")
    nhdr("nhdr_data_file_absent", {"data file": "does_not_exist.raw"},
         "detached header naming a file that does not exist")
    header_case("nhdr_list_short", "nhdr",
                nrrd_header_bytes(NRRD_FIELDS + ["data file: LIST", "_slice00.raw",
                                                 "_slice01.raw"], detached=True),
                "a LIST of 2 data files for 16 slices")
    mha("mha_type_garbled", {"ElementType": "MET_FLOA\x13"}, "ElementType = MET_FLOA\\x13")
    mha("mha_type_unknown", {"ElementType": "MET_QUAD"}, "ElementType = MET_QUAD")
    mha("mha_type_missing", {"ElementType": None}, "no ElementType")
    mha("mha_ndims_garbled", {"NDims": "3\x13"}, "NDims = 3\\x13")
    mha("mha_ndims_zero", {"NDims": "0"}, "NDims = 0")
    mha("mha_ndims_negative", {"NDims": "-3"}, "NDims = -3 (MetaIO loops forever)")
    mha("mha_ndims_one", {"NDims": "1", "DimSize": "32", "ElementSpacing": "1"},
        "a 1D image", payload=ball[:32])
    mha("mha_dimsize_short", {"DimSize": "16 16"}, "DimSize with 2 values, NDims 3")
    mha("mha_dimsize_long", {"DimSize": "16 16 16 16"}, "DimSize with 4 values, NDims 3")
    mha("mha_dimsize_missing", {"DimSize": None}, "no DimSize")
    mha("mha_dimsize_garbled", {"DimSize": "16 1\x136 16"}, "DimSize = 16 1\\x136 16")
    mha("mha_dimsize_huge", {"DimSize": "500000 500000 500000"}, "DimSize = 500000^3")
    header_case("mha_dimsize_before_ndims", "mha",
                mha_header_bytes(["DimSize = 16 16 16", "NDims = 3", "ElementType = MET_UCHAR",
                                  "ElementDataFile = LOCAL"], ball), "DimSize before NDims")
    mha("mha_compressed_garbled", {"CompressedData": "Tr\x13e"}, "CompressedData = Tr\\x13e")
    mha("mha_compressed_number", {"CompressedData": "2"}, "CompressedData = 2")
    mha("mha_channels_zero", {"ElementNumberOfChannels": "0"}, "ElementNumberOfChannels = 0")
    mha("mha_channels_negative", {"ElementNumberOfChannels": "-4"},
        "ElementNumberOfChannels = -4")
    mha("mha_channels_huge", {"ElementNumberOfChannels": "1000000"},
        "ElementNumberOfChannels = 1000000")
    mha("mha_channels_garbled", {"ElementNumberOfChannels": "1\xff"},
        "ElementNumberOfChannels = 1\\xff")
    mha("mha_byte_order_garbled", {"ElementByteOrderMSB": "Fa\x13se"},
        "ElementByteOrderMSB = Fa\\x13se")
    mha("mha_binary_byte_order_garbled", {"BinaryDataByteOrderMSB": "\x13"},
        "BinaryDataByteOrderMSB = \\x13")
    mha("mha_key_garbled", {"ObjectType": None, "Ob\x8bectType": "Image"},
        "key Ob\\x8bectType")
    mha("mha_data_file_missing", {"ElementDataFile": None}, "no ElementDataFile")
    mha("mha_data_file_absent", {"ElementDataFile": "does_not_exist.raw"},
        "ElementDataFile naming a file that does not exist", payload=b"")
    mha("mha_data_file_pattern_s", {"ElementDataFile": "_slice%s.raw 0 3 1"},
        "ElementDataFile pattern with %s (MetaIO crashes)", payload=b"")
    mha("mha_data_file_step_zero", {"ElementDataFile": "_slice%02d.raw 0 15 0"},
        "ElementDataFile pattern with step 0 (MetaIO divides by it)", payload=b"")
    mha("mha_data_file_list_empty", {"ElementDataFile": "LIST"},
        "ElementDataFile = LIST naming no file", payload=b"")

    # ---- odd scalar types --------------------------------------------------------------
    K = "scalar_type"
    n = 16 ** 3
    ball = sphere_values(dims)
    image_case(corpus, K, "vti_char", "vti",
               vti_bytes(dims, arrays=[("density", "int8", 1, pack("int8", [v / 2.0 - 64 for v in ball]))]),
               None, "Int8 scalars from -64 to 63")
    image_case(corpus, K, "mha_char", "mha", mha_bytes(dims, kind="int8",
               payload=pack("int8", [v / 2.0 - 64 for v in ball])), None, "MET_CHAR scalars")
    image_case(corpus, K, "vti_uint64_huge", "vti",
               vti_bytes(dims, arrays=[("density", "uint64", 1,
                                        pack("uint64", [v * 7.2e16 for v in ball]))]),
               None, "UInt64 scalars up to 1.8e19")
    special = [NAN if i % 7 == 0 else INF if i % 11 == 0 else -INF if i % 13 == 0 else v
               for i, v in enumerate(ball)]
    image_case(corpus, K, "vti_double_nan_inf", "vti",
               vti_bytes(dims, arrays=[("density", "float64", 1, pack("float64", special))]),
               None, "Float64 with NaN, +Inf and -Inf voxels")
    image_case(corpus, K, "vti_double_all_nan", "vti",
               vti_bytes(dims, arrays=[("density", "float64", 1, pack("float64", [NAN] * n))]),
               None, "every voxel NaN")
    image_case(corpus, K, "vti_float_huge", "vti",
               vti_bytes(dims, arrays=[("density", "float32", 1,
                                        pack("float32", [v * 1e36 for v in ball]))]),
               None, "Float32 up to 2.5e38")
    image_case(corpus, K, "vti_constant", "vti",
               vti_bytes(dims, arrays=[("density", "uint8", 1, pack("uint8", [7] * n))]),
               None, "constant scalars (empty range)")
    image_case(corpus, K, "vti_rgb", "vti",
               vti_bytes(dims, arrays=[("color", "uint8", 3, pack("uint8", ball * 3))]),
               None, "3-component scalars only")
    image_case(corpus, K, "vti_no_scalars", "vti", vti_bytes(dims, arrays=[]), "error",
               "no point arrays at all")
    image_case(corpus, K, "mha_three_channels", "mha", mha_bytes(dims, channels=3), None,
               "ElementNumberOfChannels 3")

    # ---- bad settings for the CLI ----------------------------------------------------------
    C = "config"

    def config(case, settings, note="", grid=False, text=None, expect_cli="error"):
        """A settings file paired with the spheres phantom, or (grid=True, for the keys
        only grids read) with the valid grid and its fast settings, read first so that
        the case's own value wins."""
        data = text.encode() if text is not None else json.dumps(settings).encode()
        name = "%s__%s.json" % (C, case)
        if grid:
            cli = SMALL + ["--config", GRID_CONFIG, "--config", name, "control__tets.vtu"]
        else:
            cli = SMALL + ["--config", name] + PHANTOM
        corpus.add(C, case, "json", data, cli_args=cli,
                   expect={"cli": expect_cli} if expect_cli else None, note=note)

    def light(**kw):
        base = {"type": "directional", "position": [0.5, 0.5, 2.0], "relative": True}
        base.update(kw)
        return base

    # One value of the wrong type for each key the CLI reads.
    wrong = [("method_number", {"method": 5}), ("resolution_scale_string", {"resolution_scale": "half"}),
             ("image_size_string", {"image_size": "big"}), ("output_number", {"output": 5}),
             ("output_no_dir", {"output": "/nonexistent/dir/x.png"}),
             ("ambient_string", {"ambient": "x"}), ("diffuse_list", {"diffuse": [1]}),
             ("background_string", {"background": "black"}),
             ("gradient_shading_string", {"gradient_shading": "yes"}),
             ("chromatic_attenuation_string", {"chromatic_attenuation": "yes"}),
             ("filter_width_string", {"method": "filtered", "filter_width": "wide"}),
             ("ambient_occlusion_string", {"ambient_occlusion": "some"}),
             ("lights_number", {"lights": 3}), ("light_not_object", {"lights": [5]}),
             ("light_type_number", {"lights": [light(type=7)]}),
             ("light_position_string", {"lights": [light(position="x")]}),
             ("light_focal_point_string", {"lights": [light(focal_point=["a", "b", "c"])]}),
             ("light_cone_angle_string", {"lights": [light(type="spot", cone_angle="wide")]}),
             ("light_relative_string", {"lights": [light(relative="yes")]}),
             ("light_color_string", {"lights": [light(color="red")]}),
             ("light_intensity_string", {"lights": [light(intensity="bright")]}),
             ("light_on_string", {"lights": [light(on="yes")]}),
             ("light_exponent_null", {"lights": [light(type="spot", exponent=None)]}),
             ("transfer_function_number", {"transfer_function": 3}),
             ("tf_relative_string", {"transfer_function": {"relative": "yes"}}),
             ("tf_color_string", {"transfer_function": {"color": "x"}}),
             ("tf_opacity_short", {"transfer_function": {"opacity": [[0]]}}),
             ("tf_unit_distance_string", {"transfer_function": {"unit_distance": "x"}}),
             ("camera_number", {"camera": 3}), ("camera_zoom_string", {"camera": {"zoom": "x"}})]
    for case, settings in wrong:
        config(case, settings, "a value of the wrong type")
    for case, settings in (("level0_resolution_string", {"level0_resolution": "x"}),
                           ("absorption_string", {"absorption": "x"}),
                           ("scattering_string", {"scattering": "x"})):
        config(case, settings, "grid key of the wrong type", grid=True)
    # Numbers that are valid JSON but absurd.
    far = [("directional_far_1e200", [light(position=[1e200, 1e200, 1e200], relative=False,
                                            focal_point=[0.5, 0.5, 0.5])]),
           ("directional_far_1e308", [light(position=[1e308, 0.5, 0.5])]),
           ("point_at_1e200", [light(type="point", position=[1e200, 1e200, 1e200], relative=False)]),
           ("spot_at_1e200", [light(type="spot", position=[-1e200, 0.5, 0.5], relative=False)]),
           ("directional_zero_direction", [light(position=[0.5, 0.5, 0.5], focal_point=[0.5, 0.5, 0.5])]),
           ("point_inside_volume", [light(type="point", position=[0.5, 0.5, 0.5])]),
           ("intensity_1e10", [light(intensity=1e10)]),
           ("cone_angle_negative", [light(type="spot", cone_angle=-30, position=[0.5, 0.5, 2])]),
           ("no_lights", []), ("fifty_lights", [light(type="point", position=[i / 10.0, 2.0, 0.3])
                                                for i in range(50)])]
    for case, lights in far:
        config(case, {"lights": lights, "image_size": [64, 64]}, "absurd light values",
               expect_cli=None)
    numbers = [("unit_distance_1e-300", {"transfer_function": {"unit_distance": 1e-300}}),
               ("resolution_scale_zero", {"resolution_scale": 0}),
               ("resolution_scale_0_3", {"resolution_scale": 0.3}),
               ("image_size_zero", {"image_size": [0, 0]}), ("image_size_1e9", {"image_size": [1e9, 1e9]}),
               ("filter_width_1e9", {"method": "filtered", "filter_width": 1e9}),
               ("filter_width_negative", {"method": "filtered", "filter_width": -3}),
               ("ambient_occlusion_1e300", {"ambient_occlusion": 1e300,
                                            "ambient_occlusion_radius": 1e300}),
               ("camera_zoom_zero", {"camera": {"zoom": 0}}),
               ("method_unknown", {"method": "bogus"})]
    for case, settings in numbers:
        config(case, settings, "absurd numbers", expect_cli=None)
    for case, settings in (("level0_resolution_1e12", {"level0_resolution": 1e12}),
                           ("level0_resolution_zero", {"level0_resolution": 0}),
                           ("absorption_negative", {"absorption": -1}),
                           ("scattering_1e308", {"scattering": [1e308, 1e308, 1e308]})):
        config(case, settings, "absurd grid numbers", grid=True, expect_cli=None)
    config("nan_literal", None, "NaN is not JSON", text='{"ambient": NaN, "image_size": [64, 64]}')
    config("truncated", None, "cut in the middle", text='{"lights": [ {"type": "point", "position": [1, 2 ')
    config("top_level_list", [1, 2, 3], "an array, not an object")
    config("deep_nesting", None, "10000 nested lists", text="[" * 10000 + "]" * 10000)

    # ---- bad command lines ---------------------------------------------------------------
    L = "cli_args"
    for case, args in (("size_nan", ["--size", "nan", "nan"] + PHANTOM),
                       ("size_1e9", ["--size", "1e9", "1e9"] + PHANTOM),
                       ("dims_1e12", ["--phantom", "spheres", "--dims", "1e12"]),
                       ("dims_nan", SMALL + ["--phantom", "spheres", "--dims", "nan"]),
                       ("scale_nan", SMALL + ["--scale", "nan"] + PHANTOM),
                       ("scale_negative", SMALL + ["--scale", "-0.5", "--method", "filtered"] + PHANTOM),
                       ("missing_file", SMALL + ["does_not_exist.vti"]),
                       ("directory_as_input", SMALL + ["."]),
                       ("option_without_value", SMALL + PHANTOM + ["--config"])):
        corpus.add(L, case, "args", (" ".join(args) + "\n").encode(), cli_args=args,
                   expect={"cli": "error"}, note="command line: " + " ".join(args))

    # ---- bad unstructured grids --------------------------------------------------------------
    G = "grid"

    def grid_case(case, points, cells, arrays=None, expect_cli="error", cell_arrays=(), note=""):
        if arrays is None:
            arrays = [("density", 1, ball_scalars(points))]
        corpus.add(G, case, "vtu", vtu_bytes(points, cells, arrays, cell_arrays), cli_args="auto",
                   filters=GRID_FILTERS, expect={"cli": expect_cli} if expect_cli else None,
                   note=note)

    s = ball_scalars(tets_pts)
    grid_case("scalars_more_tuples", tets_pts, tets, [("density", 1, s + [0.5] * 20)],
              expect_cli=None, note="64 points, 84 scalar values (the reader reads 64)")
    for case, count in (("scalars_more_tuples_in_memory", 20), ("scalars_fewer_tuples_in_memory", -24)):
        corpus.add(G, case, "vtu", valid_vtu, filters=GRID_FILTERS, prepare={"scalar_tuples": count},
                   expect={"UnstructuredGridIllumination": "error"},
                   note="valid file; in memory the scalars get %+d tuples" % count)
        corpus.add(K, case, "vti", valid_vti, filters=IMAGE_FILTERS[:3], prepare={"scalar_tuples": count},
                   expect={f: "error" for f in IMAGE_FILTERS[:3]},
                   note="valid file; in memory the scalars get %+d tuples" % count)
    grid_case("scalars_fewer_tuples", tets_pts, tets, [("density", 1, s[:40])],
              note="64 points, 40 scalar tuples")
    nan_pts = list(tets_pts)
    nan_pts[21] = (NAN, nan_pts[21][1], nan_pts[21][2])
    grid_case("nan_vertex", nan_pts, tets, note="one NaN vertex coordinate (interior)")
    inf_pts = list(tets_pts)
    inf_pts[0] = (INF, 0.0, 0.0)
    grid_case("inf_vertex", inf_pts, tets, note="one infinite vertex coordinate")
    grid_case("huge_coordinates", [(x * 1e300, y * 1e300, z * 1e300) for x, y, z in tets_pts],
              tets, [("density", 1, s)], expect_cli=None, note="coordinates up to 1e300")
    bad = list(tets)
    bad[5] = (VTK_TETRA, [0, 1, 1000, 3])
    grid_case("tet_id_out_of_range", tets_pts, bad, note="one tetrahedron with point id 1000")
    bad = list(tets)
    bad[7] = (VTK_TETRA, [-1, 1, 2, 3])
    grid_case("tet_id_negative", tets_pts, bad, note="one tetrahedron with point id -1")
    hex_pts, hexes = hex_grid()
    bad = list(hexes)
    bad[3] = (VTK_HEXAHEDRON, bad[3][1][:7] + [5000])
    grid_case("hex_id_out_of_range", hex_pts, bad, note="one hexahedron with point id 5000")
    grid_case("hexahedra", hex_pts, hexes, expect_cli=None, note="valid hexahedra (split)")
    flat_pts, flat_tets = tet_grid(flat=True)
    grid_case("flat_tets_only", flat_pts, flat_tets, note="every tetrahedron has zero volume")
    wedge_pts, wedges = wedge_grid()
    grid_case("wedges", wedge_pts, wedges, expect_cli=None, note="wedges only")
    pyr_pts, pyramids = pyramid_grid()
    grid_case("pyramids", pyr_pts, pyramids, expect_cli=None, note="pyramids only")
    grid_case("polygon_only", tets_pts, [(VTK_POLYGON, [0, 1, 5, 4])], note="a single polygon")
    grid_case("tets_and_polygon", tets_pts, tets + [(VTK_POLYGON, [0, 1, 5, 4])], expect_cli=None,
              note="tetrahedra plus a polygon")
    grid_case("empty", [], [], [("density", 1, [])], note="no points, no cells")
    grid_case("points_no_cells", tets_pts, [], note="points and scalars but no cells")
    surface_pts = cube_points()
    grid_case("triangles_only", surface_pts, [(VTK_TRIANGLE, t) for t in CUBE_TRIANGLES],
              note="a closed triangle surface: 2D cells only")
    grid_case("inverted_tets", tets_pts, [(t, [ids[1], ids[0], ids[2], ids[3]]) for t, ids in tets],
              expect_cli=None, note="every tetrahedron inverted (must be reoriented)")
    grid_case("no_scalars", tets_pts, tets, [], note="no point arrays")
    grid_case("rgb_scalars", tets_pts, tets, [("color", 3, s * 3)], expect_cli=None,
              note="3-component point scalars (lit by their magnitude)")
    grid_case("nan_scalars", tets_pts, tets, [("density", 1, [NAN if i % 3 else v for i, v in enumerate(s)])],
              expect_cli=None, note="two thirds of the scalars NaN")
    grid_case("cell_type_99", tets_pts, [(99, ids) for _, ids in tets], note="unknown cell type 99")

    # ---- bad surfaces for TetGen ---------------------------------------------------------------
    P = "surface"

    def surface(case, points, polys, lines=(), note=""):
        corpus.add(P, case, "vtp", vtp_bytes(points, polys, lines), filters=SURFACE_FILTERS, note=note)

    surface("flat_closed", [(x, y, 0.0) for x, y, _ in cube_points()], CUBE_TRIANGLES,
            note="closed cube squashed into the plane z = 0")
    nan_cube = cube_points()
    nan_cube[6] = (NAN, 1.0, 1.0)
    surface("nan_point", nan_cube, CUBE_TRIANGLES, note="closed cube with one NaN point")
    surface("open", cube_points(), CUBE_TRIANGLES[:-2], note="cube without one face")
    surface("self_intersecting", cube_points() + cube_points(1.0, (0.5, 0.5, 0.5)),
            CUBE_TRIANGLES + [[i + 8 for i in t] for t in CUBE_TRIANGLES],
            note="two overlapping closed cubes in one surface")
    surface("non_manifold", cube_points() + [(0.5, -1.0, -1.0)], CUBE_TRIANGLES + [[0, 1, 8]],
            note="a fin triangle on a cube edge (edge shared by 3 triangles)")
    surface("degenerate_triangles", cube_points(), CUBE_TRIANGLES + [[0, 0, 1], [2, 2, 2]],
            note="cube plus zero-area triangles")
    surface("huge_coordinates", cube_points(1e300), CUBE_TRIANGLES, note="cube of side 1e300")
    surface("tiny_coordinates", cube_points(1e-300), CUBE_TRIANGLES, note="cube of side 1e-300")
    surface("point_id_out_of_range", cube_points(), CUBE_TRIANGLES[:-1] + [[0, 7, 300]],
            note="a triangle with point id 300")
    surface("empty", [], [], note="no points, no cells")
    surface("lines_only", cube_points(), [], lines=[[0, 1], [1, 2], [2, 3]], note="lines only")

    # ---- bad filter properties in pvpython (on valid inputs) ------------------------------------
    F = "filter_props"
    image_filters = IMAGE_FILTERS[:3]

    def lights_row(positional, position, focal=(8.0, 8.0, 8.0), intensity=1.0, cone=180.0):
        return [positional] + list(position) + list(focal) + [1, 1, 1, intensity, cone, 1, 1]

    def props(case, data, ext, filters, properties=None, then=None, note="", expect=None):
        corpus.add(F, case, ext, data, filters=filters, properties=properties, then=then,
                   note=note, expect=expect)

    for case, row in (("directional_far_1e200", lights_row(0, (1e200, 1e200, 1e200))),
                      ("point_at_1e200", lights_row(1, (1e200, 8, 8))),
                      ("intensity_nan", lights_row(0, (8, 8, 40), intensity=NAN)),
                      ("intensity_1e10", lights_row(0, (8, 8, 40), intensity=1e10)),
                      ("position_inf", lights_row(1, (INF, 8, 8)))):
        props(case, valid_vti, "vti", image_filters,
              {f: {"Lights": row} for f in image_filters}, note="Lights = " + str(row))
    props("lights_13_values", valid_vti, "vti", image_filters,
          then={f: {"Lights": lights_row(0, (8, 8, 40))[:13]} for f in image_filters},
          note="a valid update, then a Lights list of 13 numbers",
          expect={f: "error" for f in image_filters})
    props("far_light_after_good_update", valid_vti, "vti", image_filters,
          then={f: {"Lights": lights_row(0, (1e200, 8, 8))} for f in image_filters},
          note="selective update to a light at 1e200")
    props("unit_distance_1e-300", valid_vti, "vti", image_filters,
          {f: {"ScalarOpacityUnitDistance": 1e-300} for f in image_filters})
    props("resolution_scale_nan", valid_vti, "vti", image_filters,
          {f: {"ResolutionScale": NAN} for f in image_filters},
          expect={f: "error" for f in image_filters})
    props("ambient_occlusion_nan", valid_vti, "vti", image_filters,
          {f: {"AmbientOcclusion": NAN, "AmbientOcclusionRadius": NAN} for f in image_filters},
          expect={f: "error" for f in image_filters})
    props("ambient_occlusion_radius_1e300", valid_vti, "vti", image_filters,
          {f: {"AmbientOcclusion": 1.0, "AmbientOcclusionRadius": 1e300} for f in image_filters})
    props("filter_width_1e9", valid_vti, "vti", ["FilteredVolumetricShadows"],
          {"FilteredVolumetricShadows": {"FilterWidth": 1e9}})
    props("absorption_nan", valid_vtu, "vtu", GRID_FILTERS,
          {"UnstructuredGridIllumination": {"Absorption": NAN}},
          expect={"UnstructuredGridIllumination": "error"})
    props("scattering_nan", valid_vtu, "vtu", GRID_FILTERS,
          {"UnstructuredGridIllumination": {"ScatteringStrength": [NAN, 0.1, 0.1]}},
          expect={"UnstructuredGridIllumination": "error"})
    props("level0_resolution_huge", valid_vtu, "vtu", GRID_FILTERS,
          {"UnstructuredGridIllumination": {"Level0Resolution": [100000, 100000, 100000]}},
          expect={"UnstructuredGridIllumination": "error"})
    props("grid_point_at_1e200", valid_vtu, "vtu", GRID_FILTERS,
          {"UnstructuredGridIllumination": {"Lights": lights_row(1, (1e200, 0.5, 0.5), (0.5, 0.5, 0.5))}})
    props("tetgen_max_volume_1e-9", valid_vtp, "vtp", SURFACE_FILTERS,
          {"TetrahedralizeSurfaceTetGen": {"MaximumVolume": 1e-9}},
          note="would make ~1e9 tetrahedra", expect={"TetrahedralizeSurfaceTetGen": "error"})
    props("cgal_cell_size_1e-4", valid_vti, "vti", ["AdaptiveTetrahedralMeshCGAL"],
          {"AdaptiveTetrahedralMeshCGAL": {"CellSize": 1e-4, "FacetDistance": 1e-4}},
          note="would make ~1e13 tetrahedra", expect={"AdaptiveTetrahedralMeshCGAL": "error"})


def main(argv):
    if len(argv) != 2:
        sys.stderr.write(__doc__)
        return 2
    root = argv[1]
    os.makedirs(root, exist_ok=True)
    corpus = Corpus(root)
    build(corpus)
    with open(os.path.join(root, "cases.json"), "w") as f:
        json.dump(corpus.cases, f, indent=1)
        f.write("\n")
    classes = {}
    for case in corpus.cases:
        classes[case["class"]] = classes.get(case["class"], 0) + 1
    print("wrote %d cases to %s (%s)" % (len(corpus.cases), root,
                                         ", ".join("%s %d" % kv for kv in classes.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
