"""pvpython: every illumination filter under MPI gives the serial result.

The driver runs the worker below once serially (pvpython) and once under
`MPIEXEC -np N pvbatch` for each N given. The worker reads the shipped CT head with
ParaView's image reader (each process reads its own piece of the extent) and a
tetrahedral grid with the unstructured reader, lights them with every filter and writes
.pvti/.pvtu files (one piece per process). The driver then reads every file back whole
and checks, against the serial run:
- Multi-Light Illumination Volume, Filtered Volumetric Shadows, Ray-Marched Illumination
  and Unstructured Grid Illumination (pieces from RedistributeDataSet, with and without
  point global ids telling the grid's coincident seam points apart, then Generate Global
  Ids; D3's pieces with ghost cells and D3's point global ids, and with the cells across a
  boundary in both pieces (D3's "Duplicate cells" mode); the reader's pieces, where
  all but one process hold nothing), an image of one cell (all but one process have an
  empty block), and images whose producers make their own pieces (Resample To Image of the
  grid, with its geometry in the data only; a MetaImage file, which only process 0 reads):
  largest difference / largest value <= 1e-5 (points matched by their coordinates);
- a one-light change in parallel is a selective update (UpdateMode 1) and equals a fresh
  parallel filter with the new lights;
- Multi-Light Illumination Volume sweeps over bands of rows without assembling the input,
  with directional lights (scale 1/2 grey and scale 1 chromatic; a light almost along z
  whose sweep along x reads more lattice rows either side of a band than the bands of 3
  processes hold), a point light beside the
  volume, and a point light inside it with a spot light below it: each process classified
  its block (ClassifiedPoints) and, but with the light inside, held bands of the
  classification smaller than the input (BandPoints); two edits of one light (the second subtracts its record) are selective and
  equal a fresh filter, with directional lights and with the point light moved; DistributedSweeps
  off assembles the input; the image of one cell (one process sweeps, the others take part
  in the collective calls only); a filter whose lights switch between directional only and
  a point light, also on the image of one cell; a new opacity function after an update over
  bands;
- an update over bands reports its progress after every slice of its sweeps, rising to 1;
- the files read back whole (the image pieces cover the illumination grid);
- a tetrahedralised Wavelet (thin layers of other pieces' cells, a level-1 walk of three
  mean edges, strong scattering) on redistributed pieces equals the serial run too;
- Unstructured Grid Illumination on redistributed pieces: no process lit the whole grid
  (its piece and the cells near it: the LitPoints field of each piece);
- hexahedra (VTK's Wavelet on 13^3 points) in D3's pieces: each piece splits a cell into
  tetrahedra as the serial run does, whatever its numbering of the points;
- a grid in two pieces, tetrahedra and triangles (a process holding 2D cells only outputs
  its points, lit as serially);
- Ray-Marched Illumination, and Filtered Volumetric Shadows with directional lights (hard
  and soft shadows): no process classified the whole input (each marches through its block
  and builds its tables' windows over it: the ClassifiedPoints field of each piece); the
  ray marcher also on the image of one cell;
- cell scalars (each point the average of the cells around it: a block's cells and a layer
  of its neighbours'), with the ray marcher, filtered shadows and the propagation (whose
  one-light edit stays selective): no process classified the whole input;
- pieces of another decomposition (slabs along x cut away from the blocks' boundaries, one
  process empty on 3; the whole image on the first process, none on the others), point and
  cell scalars, with the three image filters: each process classified only its block
  (gathered from the pieces) and outputs the illumination over it, and a light edit stays
  selective;
- no process prints an error (an empty piece is normal in parallel);
- on 2 processes, refusals: slabs that leave part of the image uncovered and a piece
  without the lit array (every image filter; only that piece's process prints why), and
  unstructured pieces that cannot join (a NaN coordinate on one process, the
  lit array missing there or given as cell data): a clear error and an empty output, no
  crash, and the pieces lit again once sound.
Usage: pvpython TestParallelIllumination.py PLUGIN OUTPUT_DIR PVBATCH MPIEXEC "MPI_FLAGS"
       GRID NPROCS...
"""
import json
import os
import re
import shutil
import subprocess
import sys

TOLERANCE = 1e-5  # largest difference relative to the largest value
FILES = ["multilight.pvti", "selective.pvti", "fresh.pvti", "swept.pvti", "swept_chromatic.pvti",
         "swept_selective.pvti", "swept_again.pvti", "swept_fresh.pvti", "swept_assembled.pvti",
         "tiny_swept.pvti", "switched.pvti", "swept_inside.pvti", "tiny_switched.pvti",
         "swept_reclassified.pvti",
         "filtered.pvti", "filtered_hard.pvti",
         "filtered_soft.pvti", "filtered_axis.pvti", "filtered_point.pvti",
         "filtered_inside.pvti", "filtered_assembled.pvti", "filtered_sized.pvti",
         "filtered_ambient.pvti", "swept_ambient.pvti",
         "swept_grazing.pvti",
         "raymarched.pvti",
         "tiny.pvti", "tiny_raymarched.pvti", "cells_raymarched.pvti", "cells_filtered.pvti",
         "cells_multilight.pvti", "slabs_multilight.pvti", "slabs_filtered.pvti",
         "slabs_raymarched.pvti", "slabs_cells.pvti", "root_multilight.pvti",
         "root_filtered.pvti",
         "unstructured.pvtu", "unstructured_ids.pvtu", "unstructured_pieces.pvtu",
         "unstructured_d3.pvtu", "unstructured_d3_duplicated.pvtu", "unstructured_generated.pvtu",
         "wavelet.pvtu", "hexahedra.pvtu", "mixed.pvtu",
         "resampled_multilight.pvti", "resampled_filtered.pvti", "resampled_raymarched.pvti",
         "metaimage_multilight.pvti"]
HEAD = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data", "headsq.vti")

# Two lights (14 numbers each, see the filters' Lights property): an orange directional
# light from above and the side, a blue point light; the edit moves and dims the second.
LIGHTS = [0, -200, -150, 400, 100, 100, 70, 1.0, 0.7, 0.4, 1.0, 90, 1, 1,
          1, 350, 120, 60, 100, 100, 70, 0.4, 0.6, 1.0, 1.0, 90, 1, 1]
EDITED = LIGHTS[:14] + [1, 330, -40, 90, 100, 100, 70, 0.4, 0.6, 1.0, 0.8, 90, 1, 1]
# The two lights with sizes (the Lights' 15th number): 4 degrees across, radius 3.
SIZED = LIGHTS[:14] + [4] + LIGHTS[14:] + [3]
# Three directional lights (swept over bands of rows in parallel: every process sweeps its
# rows, neighbouring bands exchanging lattice rows after every slice), the second edited
# twice.
SWEPT = LIGHTS[:14] + [0, 300, 250, -100, 100, 100, 70, 0.3, 0.8, 1.0, 1.0, 90, 1, 1,
                       0, 40, 90, 380, 100, 100, 70, 1.0, 1.0, 1.0, 0.6, 90, 1, 1]
# Slabs of the CT head along x per number of processes, one per process, cut where no block
# of vtkExtentTranslator's has a boundary (pieces of another decomposition); "first" and
# "last" stand for the image's first and last x, None for no piece.
SLABS = {1: [("first", "last")], 2: [("first", 20), (20, "last")],
         3: [("first", 11), (11, "last"), None]}
# The whole image on the first process, none on the others (a simulation that gathers to one).
ROOT = {1: [("first", "last")], 2: [("first", "last"), None], 3: [("first", "last"), None, None]}
GRAZING = [0, 52, 100, -326, 100, 100, 70, 1.0, 0.9, 0.8, 1.0, 90, 1, 1]
SWEPT_EDITED = SWEPT[:14] + [0, 320, 200, -60] + SWEPT[18:]
SWEPT_AGAIN = SWEPT[:14] + [0, 280, 260, 140, 100, 100, 70, 0.3, 0.8, 1.0, 0.9, 90, 1, 1] + \
    SWEPT[28:]


def selective_edits(name):
    """Properties that make a filter's edit of one of two lights (LIGHTS to EDITED) selective:
    the propagation's cost estimate recomputes both lights (the cheaper update), Changed
    Light Fraction removes and adds the edited one."""
    return {"CostEstimate": 0} if name == "MultiLightIlluminationVolume" else {}


def worker(plugin, out, grid_file, tiny_file, parallel):
    from paraview.simple import (LoadPlugin, XMLImageDataReader, XMLUnstructuredGridReader,
                                 XMLPartitionedUnstructuredGridReader, PointDatatoCellData,
                                 ProgrammableFilter, RedistributeDataSet, D3, GenerateGlobalIds,
                                 ResampleToImage, OpenDataFile,
                                 GetColorTransferFunction,
                                 GetOpacityTransferFunction, SaveData)
    ns = globals()
    LoadPlugin(plugin, remote=False, ns=ns)
    lut = GetColorTransferFunction("scalars")
    lut.RGBPoints = [0, 0.9, 0.8, 0.7, 1200, 1.0, 0.9, 0.8, 3000, 1.0, 1.0, 1.0]
    pwf = GetOpacityTransferFunction("scalars")
    pwf.Points = [0, 0, 0.5, 0, 500, 0, 0.5, 0, 1200, 0.3, 0.5, 0, 3000, 0.8, 0.5, 0]
    head = XMLImageDataReader(FileName=[HEAD])

    def image_filter(name, lights=LIGHTS, **properties):
        f = ns[name](Input=head, ColorTransferFunction=lut, OpacityFunction=pwf, **properties)
        f.Scalars = ["POINTS", "scalars"]
        f.Lights = lights
        return f

    def save(proxy, name):
        SaveData(os.path.join(out, name), proxy=proxy)

    # Each edit's lights, saved after the edit; then a fresh filter with the last lights (the
    # edit of two lights made selective: selective_edits).
    for edits, fresh, estimate in (([("multilight", LIGHTS), ("selective", EDITED)], "fresh", 0),
                                   ([("swept", SWEPT), ("swept_selective", SWEPT_EDITED),
                                     # the recorded light again: its record subtracted
                                     ("swept_again", SWEPT_AGAIN)], "swept_fresh", 1)):
        multilight = image_filter("MultiLightIlluminationVolume", ResolutionScale=0.5,
                                  CostEstimate=estimate)
        for name, edit in edits:
            multilight.Lights = edit
            save(multilight, name + ".pvti")
        save(image_filter("MultiLightIlluminationVolume", edits[-1][1], ResolutionScale=0.5),
             fresh + ".pvti")
    save(image_filter("MultiLightIlluminationVolume", SWEPT, ChromaticAttenuation=1),
         "swept_chromatic.pvti")
    # The progress this process's filter reports in an update over bands (after every slice).
    reporting = image_filter("MultiLightIlluminationVolume", SWEPT, ResolutionScale=0.5)
    progress = []
    algorithm = reporting.GetClientSideObject()
    algorithm.AddObserver("ProgressEvent", lambda o, e: progress.append(o.GetProgress()))
    reporting.UpdatePipeline()
    with open(os.path.join(out, "progress.json"), "w") as f:
        json.dump(progress, f)
    # One filter switching between directional lights only and a point light on.
    switched = image_filter("MultiLightIlluminationVolume", ResolutionScale=0.5)
    for lights in (SWEPT, EDITED):
        switched.Lights = lights
        switched.UpdatePipeline()
    save(switched, "switched.pvti")
    # A new opacity function after an update over bands: the bands' classification is
    # gathered again.
    reclassified = image_filter("MultiLightIlluminationVolume", SWEPT, ResolutionScale=0.5)
    reclassified.UpdatePipeline()
    steeper = GetOpacityTransferFunction("steeper")
    steeper.Points = [0, 0, 0.5, 0, 900, 0, 0.5, 0, 1500, 0.6, 0.5, 0, 3000, 0.9, 0.5, 0]
    reclassified.OpacityFunction = steeper
    save(reclassified, "swept_reclassified.pvti")
    save(image_filter("MultiLightIlluminationVolume", SWEPT, ResolutionScale=0.5,
                      DistributedSweeps=0), "swept_assembled.pvti")
    # A directional light almost along z: its sweep along x (the second group) moves its rays
    # about 18 rows of z a slice, so the bands of z rows (47 at scale 1/2) read 21 lattice rows
    # either side, more than a band of 3 processes holds: bands exchange with the bands two
    # away too.
    save(image_filter("MultiLightIlluminationVolume", GRAZING, ResolutionScale=0.5),
         "swept_grazing.pvti")
    save(image_filter("FilteredVolumetricShadows", ResolutionScale=0.5, FilterWidth=3),
         "filtered.pvti")
    # A point light inside the first block (six groups) and a spot light below the volume.
    inside = [1, 100, 95, 12, 100, 100, 70, 1.0, 0.8, 0.6, 1.0, 90, 1, 1,
              1, 100, 100, -150, 100, 100, 70, 0.5, 0.7, 1.0, 1.0, 25, 1, 1]
    save(image_filter("MultiLightIlluminationVolume", inside, ResolutionScale=0.5),
         "swept_inside.pvti")
    # Directional light only: each process builds its tables' windows over its block grown
    # by a shadow's reach and gets the cells beyond from the others (hard shadows: near
    # segments through the data; soft: the Gaussian kernel).
    # A light along the z axis: table cells centred on the data's planes, some of them the
    # planes between blocks. DistributedTables off: the input assembled on every process.
    # Point and spot lights: spherical tables' windows over the grown blocks (hard shadows
    # with near segments, a point light beside the volume; soft, a point light inside the
    # first block and a spot light below it, whose shadows cross every block). Lights of
    # finite size (15 numbers a light, the last the radius: 4 degrees, 3 units) read whole
    # tables, DistributedTables on or off.
    downward = [0, 100, 100, 400, 100, 100, 70, 1.0, 0.9, 0.8, 1.0, 90, 1, 1]
    for name, width, kernel, distributed, light in (
            ("filtered_hard.pvti", 0, "Box", 1, LIGHTS[:14]),
            ("filtered_soft.pvti", 3, "Gaussian", 1, LIGHTS[:14]),
            ("filtered_axis.pvti", 0, "Box", 1, downward),
            ("filtered_point.pvti", 0, "Box", 1, LIGHTS),
            ("filtered_inside.pvti", 3, "Box", 1, inside),
            ("filtered_assembled.pvti", 0, "Box", 0, LIGHTS[:14]),
            ("filtered_sized.pvti", 0, "Box", 1, SIZED)):
        f = image_filter("FilteredVolumetricShadows", ResolutionScale=0.5, FilterWidth=width,
                         FilterKernel=kernel, PerLightTransmittance=1,
                         DistributedTables=distributed)
        f.Lights = light
        save(f, name)
    # Ambient occlusion reads every point's neighbourhood across the pieces' faces: the
    # filters then assemble the whole input (Filtered Shadows even with DistributedTables).
    for name, filter_name, properties in (
            ("filtered_ambient.pvti", "FilteredVolumetricShadows", {"DistributedTables": 1}),
            ("swept_ambient.pvti", "MultiLightIlluminationVolume", {})):
        save(image_filter(filter_name, ResolutionScale=0.5, AmbientOcclusion=0.7,
                          AmbientOcclusionRadius=6, **properties), name)
    save(image_filter("RayMarchedIllumination", ResolutionScale=0.25), "raymarched.pvti")
    # Cell scalars (averaged onto the points: a block's cells and a layer of its neighbours').
    # The propagation's light edit must stay selective (the converted scalars are kept).
    head_cells = PointDatatoCellData(Input=head)
    for name, scale, lights, saved in (
            ("RayMarchedIllumination", 0.25, [LIGHTS], "cells_raymarched.pvti"),
            ("FilteredVolumetricShadows", 0.5, [LIGHTS], "cells_filtered.pvti"),
            ("MultiLightIlluminationVolume", 0.5, [LIGHTS, EDITED], "cells_multilight.pvti")):
        cells = ns[name](Input=head_cells, ColorTransferFunction=lut, OpacityFunction=pwf,
                         ResolutionScale=scale, **selective_edits(name))
        cells.Scalars = ["CELLS", "scalars"]
        for edit in lights:
            cells.Lights = edit
            cells.UpdatePipeline()
        save(cells, saved)
    # An image of 2 x 2 x 2 points: one cell, so all but one process have an empty block.
    tiny_image = XMLImageDataReader(FileName=[tiny_file])
    # tiny_switched: lights switched from a point light to directional only and back (one
    # process sweeps, the others have no piece).
    for name, saved, sequence in [("MultiLightIlluminationVolume", "tiny.pvti", [LIGHTS]),
                                  ("MultiLightIlluminationVolume", "tiny_swept.pvti", [SWEPT]),
                                  ("MultiLightIlluminationVolume", "tiny_switched.pvti",
                                   [LIGHTS, SWEPT, EDITED]),
                                  ("RayMarchedIllumination", "tiny_raymarched.pvti", [LIGHTS])]:
        tiny = ns[name](Input=tiny_image, ColorTransferFunction=lut, OpacityFunction=pwf)
        tiny.Scalars = ["POINTS", "scalars"]
        for lights in sequence:
            tiny.Lights = lights
            tiny.UpdatePipeline()
        save(tiny, saved)

    grid = XMLUnstructuredGridReader(FileName=[grid_file])
    association = "POINTS" if grid.PointData.keys() else "CELLS"
    scalars = (grid.PointData if association == "POINTS" else grid.CellData).keys()[0]
    ctf = GetColorTransferFunction(scalars)
    otf = GetOpacityTransferFunction(scalars)
    bounds = grid.GetDataInformation().GetBounds()
    centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
    size = max(bounds[2 * a + 1] - bounds[2 * a] for a in range(3))
    grid_lights = [0, centre[0] - size, centre[1] + size, centre[2] + 2 * size] + centre + \
        [1.0, 0.7, 0.4, 1.0, 90, 1, 1] + \
        [1, centre[0] + size, centre[1], centre[2]] + centre + [0.4, 0.6, 1.0, 1.0, 90, 1, 1]
    # The grid has coincident copies of points (a seam): without point global ids they are
    # one point, serially and in parallel (where RedistributeDataSet's pieces are joined by
    # coordinates); with global ids that tell them apart (the reader's point ids, given before
    # redistributing: one process reads the whole single-piece file) they stay distinct.
    numbered = ProgrammableFilter(Input=grid, OutputDataSetType="Same as Input", Script="""
from vtkmodules.vtkCommonCore import vtkIdTypeArray
grid = self.GetInput()
out = self.GetOutput()
out.ShallowCopy(grid)
ids = vtkIdTypeArray()
ids.SetName("PointIds")
ids.SetNumberOfTuples(grid.GetNumberOfPoints())
for i in range(grid.GetNumberOfPoints()):
    ids.SetValue(i, i)
out.GetPointData().SetGlobalIds(ids)
""")
    for name, source in [("unstructured.pvtu", RedistributeDataSet(Input=grid) if parallel
                          else grid),
                         ("unstructured_ids.pvtu", RedistributeDataSet(Input=numbered)
                          if parallel else numbered),
                         ("unstructured_pieces.pvtu", grid),
                         # D3's pieces: ghost cells, whose points the piece keeps (lit by the
                         # process whose cells hold them), and D3's point global ids.
                         ("unstructured_d3.pvtu", D3(Input=grid) if parallel else grid),
                         # D3's "Duplicate cells" mode: the cells across a boundary in both
                         # pieces, unmarked (they count once).
                         ("unstructured_d3_duplicated.pvtu",
                          D3(Input=grid, BoundaryMode="Duplicate cells") if parallel
                          else grid),
                         # Generate Global Ids after redistributing: ids that join the pieces'
                         # copies of a point (and the seam's, as coordinates do serially).
                         ("unstructured_generated.pvtu",
                          GenerateGlobalIds(Input=RedistributeDataSet(Input=grid)) if parallel
                          else GenerateGlobalIds(Input=grid))]:
        u = ns["UnstructuredGridIllumination"](Input=source, ColorTransferFunction=ctf,
                                               OpacityFunction=otf, Level0Resolution=[32, 32, 32],
                                               ScatteringStrength=[0.2, 0.2, 0.2])
        u.Scalars = [association, scalars]
        u.Lights = grid_lights
        save(u, name)

    # Images from producers that make their own pieces: Resample To Image of the grid (it
    # splits the whole extent among the processes itself, and gives its origin and spacing
    # with the data only) and a MetaImage file of the head (a reader of one file that cannot
    # read sub-extents: process 0 reads it all). Default transfer functions (the range of all
    # pieces).
    resampled = ResampleToImage(Input=grid, SamplingDimensions=[41, 33, 29])
    metaimage = OpenDataFile(os.path.join(os.path.dirname(tiny_file), "head.mhd"))
    for name, source, array, saved in (
            ("MultiLightIlluminationVolume", resampled, scalars, "resampled_multilight.pvti"),
            ("FilteredVolumetricShadows", resampled, scalars, "resampled_filtered.pvti"),
            ("RayMarchedIllumination", resampled, scalars, "resampled_raymarched.pvti"),
            ("MultiLightIlluminationVolume", metaimage, "MetaImage", "metaimage_multilight.pvti")):
        f = ns[name](Input=source, ResolutionScale=0.5)
        f.Scalars = ["POINTS", array]
        f.Lights = grid_lights if source == resampled else LIGHTS
        save(f, saved)

    # A uniform tetrahedral grid (written by the driver: tetrahedralising each process's piece
    # of a source would split its cells differently): thin layers of other pieces' cells,
    # as deep as the level-1 walk of three mean edges (values exchanged after level 1), across
    # which scattering spreads light.
    cube = XMLUnstructuredGridReader(FileName=[os.path.join(os.path.dirname(tiny_file),
                                                            "wavelet_tets.vtu")])
    w = ns["UnstructuredGridIllumination"](Input=RedistributeDataSet(Input=cube) if parallel
                                           else cube, Level0Resolution=[16, 16, 16],
                                           Level1Iterations=3, Absorption=0.05,
                                           ScatteringStrength=[0.5, 0.5, 0.5])
    w.Scalars = ["POINTS", "RTData"]
    w.Lights = [0, -1, -2, -3, 12, 12, 12, 1.0, 0.8, 0.6, 1.0, 90, 1, 1,
                1, 30, 12, 12, 12, 12, 12, 0.5, 0.7, 1.0, 1.0, 90, 1, 1]
    save(w, "wavelet.pvtu")

    # Hexahedra in D3's pieces (numbered by D3): each piece splits its cells as the serial run.
    hexahedra = XMLUnstructuredGridReader(FileName=[os.path.join(os.path.dirname(tiny_file),
                                                                 "wavelet_hexahedra.vtu")])
    h = ns["UnstructuredGridIllumination"](Input=D3(Input=hexahedra) if parallel else hexahedra,
                                           Level0Resolution=[12, 12, 12])
    h.Scalars = ["POINTS", "RTData"]
    h.Lights = [0, -1, -2, -3, 6, 6, 6, 1.0, 0.8, 0.6, 1.0, 90, 1, 1]
    save(h, "hexahedra.pvtu")

    # Two pieces: tetrahedra, and triangles above them (on 2 processes one process holds
    # only 2D cells, whose points are lit as a single process lights them; on 3 one holds
    # nothing).
    mixed = ns["UnstructuredGridIllumination"](
        Input=XMLPartitionedUnstructuredGridReader(FileName=[os.path.join(
            os.path.dirname(tiny_file), "mixed.pvtu")]), Level0Resolution=[8, 8, 8])
    mixed.Scalars = ["POINTS", "RTData"]
    mixed.Lights = [0, -1, -2, -3, 0, 0, 0, 1.0, 0.8, 0.6, 1.0, 90, 1, 1]
    save(mixed, "mixed.pvtu")

    # Pieces of another decomposition than the blocks the filters read (as a simulation hands
    # its own over): slabs along x, cut where no block boundary lies, the third process's
    # empty, and the whole image on the first process alone; each block is gathered from the
    # pieces that hold it, and each process outputs the illumination over its block.
    # On point scalars (a light edit must stay selective) and on cell scalars. Last: a
    # programmable filter leaves numpy's max in this module.
    pieces = {(association, layout): x_slabs(source, slabs)
              for association, source in (("POINTS", head), ("CELLS", head_cells))
              for layout, slabs in (("slabs", SLABS), ("root", ROOT))}
    for name, association, layout, scale, lights, saved in (
            ("MultiLightIlluminationVolume", "POINTS", "slabs", 0.5, [LIGHTS, EDITED],
             "slabs_multilight.pvti"),
            ("FilteredVolumetricShadows", "POINTS", "slabs", 0.5, [LIGHTS], "slabs_filtered.pvti"),
            ("RayMarchedIllumination", "POINTS", "slabs", 0.25, [LIGHTS], "slabs_raymarched.pvti"),
            ("MultiLightIlluminationVolume", "CELLS", "slabs", 0.5, [SWEPT], "slabs_cells.pvti"),
            ("MultiLightIlluminationVolume", "POINTS", "root", 0.5, [LIGHTS, EDITED],
             "root_multilight.pvti"),
            ("FilteredVolumetricShadows", "CELLS", "root", 0.5, [LIGHTS], "root_filtered.pvti")):
        f = ns[name](Input=pieces[(association, layout)], ColorTransferFunction=lut,
                     OpacityFunction=pwf, ResolutionScale=scale, **selective_edits(name))
        f.Scalars = [association, "scalars"]
        for edit in lights:
            f.Lights = edit
            f.UpdatePipeline()
        save(f, saved)


def x_slabs(source, slabs):
    """A programmable filter that gives process p of N the slab slabs[N][p] of the image
    along x, reading the whole image. Its scripts run in the __main__ module of the process
    (ParaView's prelude gives it numpy's names, max among them: in the worker, this
    module): they define no other names but their functions'."""
    from paraview.simple import ProgrammableFilter
    return ProgrammableFilter(Input=source, OutputDataSetType="Same as Input",
                              RequestUpdateExtentScript="""
def _whole_input(algorithm):
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
    request = algorithm.GetInputInformation(0, 0)
    request.Set(sddp.UPDATE_PIECE_NUMBER(), 0)
    request.Set(sddp.UPDATE_NUMBER_OF_PIECES(), 1)
    request.Set(sddp.UPDATE_EXTENT(), request.Get(sddp.WHOLE_EXTENT()), 6)
_whole_input(self)
""", Script="""
def _slab(algorithm, slabs):
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    from vtkmodules.vtkImagingCore import vtkExtractVOI
    controller = vtkMultiProcessController.GetGlobalController()
    slab = slabs[controller.GetNumberOfProcesses()][controller.GetLocalProcessId()]
    e = list(algorithm.GetInput().GetExtent())
    if slab is None:
        algorithm.GetOutput().SetExtent(0, -1, 0, -1, 0, -1)
        return
    # The pipeline runs this again whenever a block is asked for that the slab does not
    # hold: the same slab again, as a simulation's unchanged piece would be.
    if not hasattr(algorithm, "slab"):
        x = [e[0] if c == "first" else e[1] if c == "last" else c for c in slab]
        algorithm.slab = vtkExtractVOI()
        algorithm.slab.SetInputData(algorithm.GetInput())
        algorithm.slab.SetVOI(x[0], x[1], e[2], e[3], e[4], e[5])
        algorithm.slab.Update()
    algorithm.GetOutput().ShallowCopy(algorithm.slab.GetOutput())
_slab(self, %r)
""" % (slabs,))


def gap_worker(plugin):
    """Slabs that leave x = 21 to 24 in no piece: every image filter must refuse them with
    an error and output nothing, and the processes go on. Unstructured pieces that cannot
    join (a bad coordinate, pieces whose arrays differ) likewise, until they are sound.
    What it prints goes to stderr, where VTK's messages go: mpirun forwards a process's
    stdout and stderr separately, so a line printed to stdout could land inside a message."""

    def report(line):
        print(line, file=sys.stderr, flush=True)

    from paraview.simple import (LoadPlugin, XMLImageDataReader, GetColorTransferFunction,
                                 GetOpacityTransferFunction)
    ns = globals()
    LoadPlugin(plugin, remote=False, ns=ns)
    gap = x_slabs(XMLImageDataReader(FileName=[HEAD]), {2: [("first", 20), (25, "last")]})
    for name in ("MultiLightIlluminationVolume", "FilteredVolumetricShadows",
                 "RayMarchedIllumination"):
        f = ns[name](Input=gap, ColorTransferFunction=GetColorTransferFunction("scalars"),
                     OpacityFunction=GetOpacityTransferFunction("scalars"))
        f.Scalars = ["POINTS", "scalars"]
        f.UpdatePipeline()
        report("%s output points: %d" % (name, f.GetDataInformation().GetNumberOfPoints()))
    # The image filters on Wavelet pieces whose last one lacks the lit array: that process
    # says so, the others stop silently.
    from paraview.simple import CleantoGrid, ProgrammableFilter, Wavelet
    lacking = ProgrammableFilter(Input=Wavelet(WholeExtent=[-8, 8] * 3),
                                 OutputDataSetType="Same as Input", Script="""
def _drop(algorithm):
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    controller = vtkMultiProcessController.GetGlobalController()
    out = algorithm.GetOutput()
    out.ShallowCopy(algorithm.GetInput())
    if controller.GetLocalProcessId() == controller.GetNumberOfProcesses() - 1:
        out.GetPointData().RemoveArray("RTData")
_drop(self)
""")
    for name in ("MultiLightIlluminationVolume", "FilteredVolumetricShadows",
                 "RayMarchedIllumination"):
        f = ns[name](Input=lacking, ResolutionScale=0.5)
        f.Scalars = ["POINTS", "RTData"]
        f.UpdatePipeline()
        report("%s without the array: output points: %d"
               % (name, f.GetDataInformation().GetNumberOfPoints()))
    # Unstructured Grid Illumination on tetrahedralised Wavelet pieces, the last process's
    # spoiled in turn (a NaN coordinate; the lit array removed; the array as cell data):
    # refused with an error and an empty output, then lit again once the pieces are sound.
    pieces = ProgrammableFilter(Input=CleantoGrid(Input=Wavelet(WholeExtent=[-5, 5] * 3)),
                                OutputDataSetType="vtkUnstructuredGrid")
    u = UnstructuredGridIllumination(Input=pieces, Level0Resolution=[12, 12, 12])
    u.Scalars = ["POINTS", "RTData"]
    u.Lights = [0, -30, -20, 40, 0, 0, 0, 1, 1, 1, 1, 90, 1, 1]
    for spoil in ("nan", "missing", "cells", "none"):
        pieces.Script = """
def _spoil(algorithm, spoil):
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
    from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    controller = vtkMultiProcessController.GetGlobalController()
    split = vtkDataSetTriangleFilter()
    split.SetInputData(algorithm.GetInput())
    split.Update()
    out = algorithm.GetOutput()
    out.ShallowCopy(split.GetOutput())
    if controller.GetLocalProcessId() != controller.GetNumberOfProcesses() - 1:
        return
    if spoil == "nan":
        points = vtkPoints()
        points.DeepCopy(out.GetPoints())  # (the input's own points are shared)
        x = points.GetPoint(3)
        points.SetPoint(3, float("nan"), x[1], x[2])
        out.SetPoints(points)
    elif spoil in ("missing", "cells"):
        out.GetPointData().RemoveArray("RTData")
    if spoil == "cells":
        cells = vtkDoubleArray()
        cells.SetName("RTData")
        cells.SetNumberOfTuples(out.GetNumberOfCells())
        cells.Fill(150.0)
        out.GetCellData().AddArray(cells)
_spoil(self, %r)
""" % spoil
        u.UpdatePipeline()
        report("UnstructuredGridIllumination %s: output points: %d"
               % (spoil, u.GetDataInformation().GetNumberOfPoints()))


def read_whole(path):
    from paraview.simple import OpenDataFile
    from paraview import servermanager
    reader = OpenDataFile(path)
    reader.UpdatePipeline()
    return servermanager.Fetch(reader)


def values_by_point(data, name):
    """The array's tuples at the distinct points, sorted by their coordinates (exact: the
    pieces hold the points the serial grid has): (coordinates, tuples), where points coincide
    the last one's tuple; None when the array is missing."""
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    array = data.GetPointData().GetArray(name)
    if array is None:
        return None
    values = vtk_to_numpy(array).reshape(-1, array.GetNumberOfComponents()).astype(numpy.float64)
    if data.GetNumberOfPoints() == 0:
        return numpy.zeros((0, 3)), values
    if data.IsA("vtkImageData"):
        extent = data.GetExtent()
        k, j, i = numpy.meshgrid(*(numpy.arange(extent[2 * a], extent[2 * a + 1] + 1)
                                   for a in (2, 1, 0)), indexing="ij")
        index = numpy.stack([i.ravel(), j.ravel(), k.ravel()], axis=1) * data.GetSpacing()
        direction = data.GetDirectionMatrix()
        rotation = [[direction.GetElement(r, c) for c in range(3)] for r in range(3)]
        points = data.GetOrigin() + index @ numpy.array(rotation).T
    else:
        points = vtk_to_numpy(data.GetPoints().GetData()).astype(numpy.float64)
    # numpy.unique keeps each row's first index: that of its last point, read backwards.
    coordinates, first = numpy.unique(points[::-1], axis=0, return_index=True)
    return coordinates, values[::-1][first]


def compare(serial, parallel, name="Illumination"):
    """Largest difference over the largest serial value (infinite where a value is not a
    finite number); None when points or the array are missing."""
    import numpy
    a = values_by_point(serial, name)
    b = values_by_point(parallel, name)
    if a is None or b is None or a[0].shape != b[0].shape or (a[0] != b[0]).any():
        return None
    inf = float("inf")
    if not (numpy.isfinite(a[1]).all() and numpy.isfinite(b[1]).all()):
        return inf
    largest = numpy.abs(a[1]).max(initial=0.0)
    difference = numpy.abs(a[1] - b[1]).max(initial=0.0)
    return float(difference / largest) if largest > 0 else (0.0 if difference == 0 else inf)


def held_less(out, run, f, field, what, held, failures):
    """Check that every process of `run` wrote image f and that the count in its field array
    `field` (points it held) is below the points the serial run classified; print them as
    `what`. Failures name what a process held whole."""
    whole = piece_counts(os.path.join(out, "serial", f[:-len(".pvti")]), "ClassifiedPoints")
    counts = piece_counts(os.path.join(out, run, f[:-len(".pvti")]), field)
    print("%-5s %-26s %s %s of %s" % (run, f, what, counts, whole))
    if len(counts) != int(run[2:]) or max(counts) >= whole[0]:
        failures.append("%s/%s: a process held the whole %s" % (run, f, held))


def piece_counts(directory, field):
    """The value of a field array (LitPoints, ClassifiedPoints) of each piece file written in
    directory."""
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLUnstructuredGridReader
    counts = []
    for name in sorted(os.listdir(directory)):
        reader = vtkXMLImageDataReader() if name.endswith(".vti") else \
            vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(directory, name))
        reader.Update()
        array = reader.GetOutput().GetFieldData().GetArray(field)
        if array:
            counts.append(int(array.GetValue(0)))
    return counts


def cell_counts(directory):
    """Ghost cells and other cells of the unstructured piece files written in directory."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    ghosts = others = 0
    for name in sorted(os.listdir(directory)):
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(directory, name))
        reader.Update()
        grid = reader.GetOutput()
        marks = grid.GetCellData().GetArray("vtkGhostType")
        marked = sum(1 for c in range(grid.GetNumberOfCells()) if marks and marks.GetValue(c))
        ghosts += marked
        others += grid.GetNumberOfCells() - marked
    return ghosts, others


def update_mode(data):
    return int(data.GetFieldData().GetArray("UpdateMode").GetValue(0))


def write_tiny_image(path):
    """An image of 2 x 2 x 2 points with the head's scalar range."""
    from IlluminatedVolumeTestUtilities import write_image
    write_image(path, (2, 2, 2), (0, 900, 1500, 3000, 2000, 1200, 2500, 600), (30, 30, 30),
                "vtkShortArray")


def write_metaimage(path):
    """The CT head as a MetaImage file (.mhd header, .raw values)."""
    from vtkmodules.vtkIOImage import vtkMetaImageWriter
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader
    reader = vtkXMLImageDataReader()
    reader.SetFileName(HEAD)
    writer = vtkMetaImageWriter()
    writer.SetInputConnection(reader.GetOutputPort())
    writer.SetFileName(path)
    writer.SetCompression(False)
    writer.Write()


def write_wavelet_tetrahedra(path):
    """VTK's Wavelet on 25^3 points split into tetrahedra."""
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(0, 24, 0, 24, 0, 24)
    split = vtkDataSetTriangleFilter()
    split.SetInputConnection(source.GetOutputPort())
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputConnection(split.GetOutputPort())
    writer.SetFileName(path)
    writer.Write()


def write_wavelet_hexahedra(path):
    """VTK's Wavelet on 13^3 points as hexahedra, the points numbered out of order (the
    filter splits the cells into tetrahedra: each piece must split a cell as the serial run
    does, whatever its numbering of the points)."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid, VTK_HEXAHEDRON
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    n = 13
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(0, n - 1, 0, n - 1, 0, n - 1)
    source.Update()
    image = source.GetOutput()
    # Image point i becomes point (i x 7919) mod n^3 (7919 is prime: a permutation).
    number = [(i * 7919) % n ** 3 for i in range(n ** 3)]
    points = vtkPoints()
    points.SetNumberOfPoints(n ** 3)
    values = image.GetPointData().GetArray("RTData").NewInstance()
    values.SetName("RTData")
    values.SetNumberOfTuples(n ** 3)
    for i in range(n ** 3):
        points.SetPoint(number[i], image.GetPoint(i))
        values.SetValue(number[i], image.GetPointData().GetArray("RTData").GetValue(i))
    grid = vtkUnstructuredGrid()
    grid.SetPoints(points)
    grid.GetPointData().SetScalars(values)
    for k in range(n - 1):
        for j in range(n - 1):
            for i in range(n - 1):
                corner = [i + n * (j + n * k) + d for d in (0, 1, n + 1, n)]
                grid.InsertNextCell(VTK_HEXAHEDRON, 8,
                                    [number[c] for c in corner + [c + n * n for c in corner]])
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetFileName(path)
    writer.Write()


def write_mixed_pieces(directory):
    """mixed.pvtu: two pieces, the tetrahedra of VTK's Wavelet on 9^3 points and a plane of
    triangles half a spacing above them (points of no 3D cell)."""
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
    from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter
    from vtkmodules.vtkFiltersCore import vtkAppendFilter
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-4, 4, -4, 4, -4, 4)
    split = vtkDataSetTriangleFilter()
    split.SetInputConnection(source.GetOutputPort())
    plane = vtkPlaneSource()
    plane.SetOrigin(-4.3, -4.3, 4.5)
    plane.SetPoint1(4.3, -4.3, 4.5)
    plane.SetPoint2(-4.3, 4.3, 4.5)
    plane.SetResolution(4, 4)
    triangles = vtkAppendFilter()
    triangles.AddInputConnection(plane.GetOutputPort())
    triangles.Update()
    values = vtkFloatArray()
    values.SetName("RTData")
    values.SetNumberOfTuples(triangles.GetOutput().GetNumberOfPoints())
    values.Fill(100.0)
    triangles.GetOutput().GetPointData().AddArray(values)
    for name, port in (("mixed_0.vtu", split.GetOutputPort()), ("mixed_1.vtu", None)):
        writer = vtkXMLUnstructuredGridWriter()
        if port:
            writer.SetInputConnection(port)
        else:
            writer.SetInputData(triangles.GetOutput())
        writer.SetDataModeToAscii()
        writer.SetFileName(os.path.join(directory, name))
        writer.Write()
    with open(os.path.join(directory, "mixed.pvtu"), "w") as f:
        f.write('<?xml version="1.0"?>\n'
                '<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">\n'
                '  <PUnstructuredGrid GhostLevel="0">\n'
                '    <PPointData><PDataArray type="Float32" Name="RTData"/></PPointData>\n'
                '    <PPoints><PDataArray type="Float32" NumberOfComponents="3"/></PPoints>\n'
                '    <Piece Source="mixed_0.vtu"/>\n'
                '    <Piece Source="mixed_1.vtu"/>\n'
                '  </PUnstructuredGrid>\n'
                '</VTKFile>\n')


def driver(plugin, out, pvbatch, mpiexec, flags, grid_file, counts):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from IlluminatedVolumeTestUtilities import environment_for_mpiexec
    failures = []
    runs = {"serial": [pvbatch]}
    for n in counts:
        runs["np" + n] = [mpiexec] + flags.split() + ["-np", n, pvbatch]
    os.makedirs(out, exist_ok=True)
    tiny_file = os.path.join(out, "tiny.vti")
    write_tiny_image(tiny_file)
    write_metaimage(os.path.join(out, "head.mhd"))
    write_wavelet_tetrahedra(os.path.join(out, "wavelet_tets.vtu"))
    write_wavelet_hexahedra(os.path.join(out, "wavelet_hexahedra.vtu"))
    write_mixed_pieces(out)
    for run, command in runs.items():
        directory = os.path.join(out, run)
        shutil.rmtree(directory, ignore_errors=True)  # no piece files of an earlier run
        os.makedirs(directory)
        result = subprocess.run(command + [os.path.abspath(__file__), "--worker", plugin, directory,
                                           grid_file, tiny_file, "0" if run == "serial" else "1"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=environment_for_mpiexec(), timeout=1200)
        log = result.stdout
        if result.returncode != 0 or "ERROR" in log or "Warning" in log:
            failures.append("%s: exit %d, output:\n%s" % (run, result.returncode, log[-3000:]))
    if "np2" in runs:
        result = subprocess.run(runs["np2"] + [os.path.abspath(__file__), "--gap", plugin],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=environment_for_mpiexec(), timeout=600)
        print(result.stdout)
        # Every process's errors are printed once, by the first process (the one whose
        # messages a client shows), naming the processes that reported them.
        # (The worker prints to stderr with the messages: mpirun forwards stdout apart.)
        errors = [line for line in result.stdout.splitlines() if "ERR|" in line]
        firsts = all("[pvbatch.0 " in line for line in errors)
        refused = result.stdout.count(
            "Processes 0-1 of 2: The pieces leave part of this process's block of the image "
            "uncovered")
        spoiled = (result.stdout.count(
            "Process 1 of 2: Point 3 of this process's piece has a coordinate that is not a "
            "finite number") == 1 and
                   result.stdout.count(
                       "Processes 0-1 of 2: The pieces' arrays to illuminate differ between "
                       "processes") == 2 and
                   result.stdout.count(
                       "Process 1 of 2: The input has no point or cell array 'RTData'") == 3 and
                   "cannot be made point scalars" not in result.stdout)
        relit = re.search(r"UnstructuredGridIllumination none: output points: [1-9]",
                          result.stdout)
        if result.returncode != 0 or refused != 3 or not spoiled or not relit or \
                not firsts or len(errors) != 9 or \
                len(re.findall(r" output points: 0(?![0-9])", result.stdout)) != 9:
            failures.append("np2 gap: exit %d, output:\n%s" % (result.returncode,
                                                                 result.stdout[-3000:]))
    if failures:
        print("\n".join(failures))
        return 1
    serial = {f: read_whole(os.path.join(out, "serial", f)) for f in FILES}
    # A light edit on cell scalars is selective serially too (the converted scalars are kept).
    if update_mode(serial["cells_multilight.pvti"]) != 1:
        failures.append("serial/cells_multilight: not a selective update")
    for run in runs:
        if run == "serial":
            continue
        # Progress in an update over bands: reported after every slice of each sweep (the
        # scale-1/2 head has 32 to 47 slices a sweep), never decreasing, the filter's own
        # reports reaching 1 (the pipeline reports 1 after it anyway).
        with open(os.path.join(out, run, "progress.json")) as f:
            progress = json.load(f)
        print("%-5s progress reported %d times, the filter's last %s" % (
            run, len(progress), progress[-2] if len(progress) > 1 else None))
        if len(progress) < 32 or progress != sorted(progress) or 1.0 not in progress[:-1]:
            failures.append("%s: progress %s" % (run, progress))
        for f in FILES:
            data = read_whole(os.path.join(out, run, f))
            if f.endswith(".pvti") and data.GetExtent() != serial[f].GetExtent():
                failures.append("%s/%s: extent %s, serial %s" % (run, f, data.GetExtent(),
                                                                   serial[f].GetExtent()))
                continue
            error = compare(serial[f], data)
            print("%-5s %-26s difference / largest value %s" % (run, f, error))
            if error is None or error > TOLERANCE:
                failures.append("%s/%s: difference %s" % (run, f, error))
            if f.startswith("unstructured") and compare(serial[f], data, "LitColors") is None:
                failures.append("%s/%s: LitColors missing" % (run, f))
            if f in ("unstructured_d3.pvtu", "unstructured_d3_duplicated.pvtu"):
                # D3 gave the pieces ghost cells (whose points the pieces keep), and in its
                # "Duplicate cells" mode cells that two pieces both hold.
                ghosts, others = cell_counts(os.path.join(out, run, f[:-len(".pvtu")]))
                whole = serial[f].GetNumberOfCells()
                print("%-5s %-26s ghost cells %d, others %d of %d" % (run, f, ghosts, others,
                                                                      whole))
                if ghosts == 0 or (others > whole) != (f == "unstructured_d3_duplicated.pvtu"):
                    failures.append("%s/%s: D3's pieces are not what the test needs" % (run, f))
            if f in ("unstructured.pvtu", "wavelet.pvtu"):
                # Each process lit its piece and the cells near it, not the whole grid.
                whole = serial[f].GetNumberOfPoints()
                lit = piece_counts(os.path.join(out, run, f[:-len(".pvtu")]), "LitPoints")
                print("%-5s %-26s points lit by each process %s of %d" % (run, f, lit, whole))
                if not lit or max(lit) >= whole:
                    failures.append("%s/%s: a process lit the whole grid" % (run, f))
            if f.endswith("_ambient.pvti"):
                ambient = compare(serial[f], data, "AmbientOcclusion")
                if ambient is None or ambient > TOLERANCE:
                    failures.append("%s/%s: AmbientOcclusion difference %s" % (run, f, ambient))
            elif f.startswith("filtered_"):
                shadow = compare(serial[f], data, "Transmittance0")
                if shadow is None or shadow > TOLERANCE:
                    failures.append("%s/%s: Transmittance0 difference %s" % (run, f, shadow))
            if f in ("swept.pvti", "swept_chromatic.pvti", "multilight.pvti",
                     "selective.pvti", "switched.pvti", "swept_inside.pvti"):
                # Each process held bands of the classification (directional lights) and
                # wedges of the point and spot lights' rays (the light beside the volume, inside
                # it, the spot light below), not all of it.
                held_less(out, run, f, "BandPoints", "largest band of each process",
                          "classification", failures)
            if f in ("raymarched.pvti", "filtered_hard.pvti", "filtered_soft.pvti",
                     "filtered_axis.pvti", "filtered_point.pvti", "filtered_inside.pvti",
                     "swept.pvti", "swept_chromatic.pvti", "multilight.pvti",
                     "swept_inside.pvti", "cells_raymarched.pvti", "cells_filtered.pvti",
                     "cells_multilight.pvti", "slabs_multilight.pvti", "slabs_filtered.pvti",
                     "slabs_raymarched.pvti", "slabs_cells.pvti", "root_multilight.pvti",
                     "root_filtered.pvti"):
                # Each process classified its block of the input, not the whole input.
                held_less(out, run, f, "ClassifiedPoints",
                          "input points classified by each process", "input", failures)
            if f in ("filtered_hard.pvti", "filtered_soft.pvti", "filtered_axis.pvti",
                     "filtered_point.pvti", "filtered_inside.pvti"):
                # Each process classified its block grown by a shadow's reach, not the whole.
                held_less(out, run, f, "GrownPoints", "grown block of each process",
                          "classification", failures)
            if f in ("filtered_assembled.pvti", "swept_assembled.pvti"):
                held = piece_counts(os.path.join(out, run, f[:-len(".pvti")]),
                                    "ClassifiedPoints")
                whole = serial[f].GetFieldData().GetArray("ClassifiedPoints").GetValue(0)
                if min(held) != whole:
                    failures.append("%s/%s: the input was not assembled" % (run, f))
        for edited, reference in (("selective", "fresh"), ("swept_again", "swept_fresh")):
            selective = read_whole(os.path.join(out, run, edited + ".pvti"))
            fresh = read_whole(os.path.join(out, run, reference + ".pvti"))
            edit_error = compare(fresh, selective)
            print("%-5s %s: UpdateMode %d, difference from a fresh filter %s"
                  % (run, edited, update_mode(selective), edit_error))
            if update_mode(selective) != 1 or edit_error is None or edit_error > TOLERANCE:
                failures.append("%s/%s: not an exact selective update" % (run, edited))
        for edited in ("swept_selective", "cells_multilight", "slabs_multilight",
                       "root_multilight"):
            if update_mode(read_whole(os.path.join(out, run, edited + ".pvti"))) != 1:
                failures.append("%s/%s: not a selective update" % (run, edited))
    print("\n".join(failures) if failures else "all parallel runs equal the serial run")
    return 1 if failures else 0


if __name__ == "__main__":
    if sys.argv[1] == "--gap":
        gap_worker(sys.argv[2])
    elif sys.argv[1] == "--worker":
        worker(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6] == "1")
    else:
        sys.exit(driver(*sys.argv[1:7], sys.argv[7:]))
