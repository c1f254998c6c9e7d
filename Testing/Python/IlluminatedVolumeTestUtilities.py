"""Helpers shared by the pvpython tests of the Illuminated Volume representation."""
import contextlib
import math
import os
import socket
import subprocess
import sys
import time

from paraview import servermanager


class Checks:
    """Prints each check as it is made and remembers the failures (for finish)."""

    def __init__(self):
        self.failures = []

    def __call__(self, condition, message):
        print(("ok    " if condition else "FAIL  ") + message)
        if not condition:
            self.failures.append(message)


def illuminated_view(source, size):
    """A new render view with the light kit off, showing source as "Illuminated Volume"
    coloured by its Density array."""
    from paraview.simple import ColorBy, CreateView, Show
    view = CreateView("RenderView")
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    view.UseLight = 0
    rep = Show(source, view)
    rep.SetRepresentationType("Illuminated Volume")
    ColorBy(rep, ("POINTS", "Density"))
    return view, rep


def scene_light(view, position, focal_point, colour, point=False, intensity=1.0):
    """A Light Inspector light in scene coordinates: directional, or a point light."""
    from paraview.simple import AddLight
    light = AddLight(view=view)
    light.Coords = "Scene"
    if point:
        light.Type = "Positional"
        light.ConeAngle = 180
    light.Position = position
    light.FocalPoint = focal_point
    light.DiffuseColor = colour
    light.Intensity = intensity
    return light


def info(rep, name):
    """A read-only property of the representation, fresh from where it rendered."""
    rep.SMProxy.UpdatePropertyInformation()
    prop = rep.SMProxy.GetProperty(name)
    return [prop.GetElement(i) for i in range(prop.GetNumberOfElements())]


def illumination_status():
    """A new IlluminationStatus proxy of the active session: the background lighting where
    the views render (the server of a client-server session). UnRegister(None) it when done."""
    status = servermanager.ProxyManager().SMProxyManager.NewProxy("misc", "IlluminationStatus")
    status.UpdateVTKObjects()
    return status


def lighting_flags(status):
    """(busy, ready): a lighting runs or is queued; a finished one waits to be drawn. Cheap to
    ask, unlike a representation's information, which includes its mean illumination."""
    status.UpdatePropertyInformation()
    return (status.GetProperty("IlluminationBusy").GetElement(0) != 0,
            status.GetProperty("IlluminationReady").GetElement(0) != 0)


def illumination_waits(status):
    """Lightings that a render of the process computed itself or waited for so far."""
    status.UpdatePropertyInformation()
    return status.GetProperty("IlluminationWaits").GetElement(0)


def lighting_pending(status):
    """Whether a lighting runs, is queued or waits to be drawn (lighting_flags)."""
    return any(lighting_flags(status))


def write_lines_and_exit(path, lines):
    """For a script run inside the GUI (paraview --script): the lines written to `path`, then
    the GUI ends at once (os._exit), as run_gui_script expects."""
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    os._exit(0)


def render_final(view):
    """Render until the view shows its final illumination; returns whether a lighting ran in
    the background meanwhile. With Asynchronous Lighting on (the GUI's default) a render
    draws the last finished illumination while the new one is computed on a worker thread; a
    script renders again once a result is ready, as the GUI's pqIlluminationLightingBehavior
    does. The status covers every representation, so a result still waiting after this view
    rendered is another view's."""
    from paraview.simple import Render
    status = illumination_status()
    Render(view)
    waited = False
    while True:
        busy, ready = lighting_flags(status)
        if not busy and not ready:
            break
        waited = True
        if ready:
            Render(view)
            busy, ready = lighting_flags(status)
            if ready and not busy:
                break  # another view's result
        time.sleep(0.02)
    status.UnRegister(None)
    return waited


def mean_illumination(proxy):
    """Mean of the Illumination point array of a filter's output (r, g, b)."""
    proxy.UpdatePipeline()
    data = servermanager.Fetch(proxy)
    array = data.GetPointData().GetArray("Illumination")
    n = array.GetNumberOfTuples()
    return [sum(array.GetComponent(i, c) for i in range(n)) / n for c in range(3)]


def relative_difference(a, b):
    return max(abs(x - y) for x, y in zip(a, b)) / max(max(abs(y) for y in b), 1e-12)


def relative_rms(values, reference):
    """RMS of values - reference over the RMS of reference (two vtkDataArrays of the same
    size, every component); infinite where the reference is all 0."""
    error = norm = 0.0
    for i in range(reference.GetNumberOfValues()):
        error += (values.GetValue(i) - reference.GetValue(i)) ** 2
        norm += reference.GetValue(i) ** 2
    return math.sqrt(error / norm) if norm > 0 else math.inf


def light_parameters(light, position, focal):
    """The 14-number layout of a view light (vtkPVLight proxy) at world position/focal."""
    positional = 1 if light.Type == "Positional" else 0
    return [positional] + list(position) + list(focal) + list(light.DiffuseColor) + \
        [light.Intensity, light.ConeAngle, 1, 1 if light.Enable else 0]


def camera_to_world(camera, point):
    """A point of a camera light's frame in world coordinates: (0, 0, 1) is the camera
    position, (0, 0, 0) the focal point, x and y scaled by the camera distance along the
    view's right and up vectors."""
    p = camera.GetPosition()
    f = camera.GetFocalPoint()
    up = camera.GetViewUp()
    back = [p[i] - f[i] for i in range(3)]
    d = math.sqrt(sum(x * x for x in back))
    z = [x / d for x in back]
    right = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]]
    norm = math.sqrt(sum(x * x for x in right))
    right = [x / norm for x in right]
    true_up = [z[1] * right[2] - z[2] * right[1], z[2] * right[0] - z[0] * right[2],
               z[0] * right[1] - z[1] * right[0]]
    return [f[i] + d * (point[0] * right[i] + point[1] * true_up[i]) + point[2] * back[i]
            for i in range(3)]


def mean_colours(path):
    """Mean red, green and blue of the pixels of a PNG that differ from its corner pixel
    (the background)."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    pixels = reader.GetOutput().GetPointData().GetScalars()
    background = [pixels.GetComponent(0, c) for c in range(3)]
    sums = [0.0, 0.0, 0.0]
    count = 0
    for i in range(pixels.GetNumberOfTuples()):
        rgb = [pixels.GetComponent(i, c) for c in range(3)]
        if rgb != background:
            sums = [s + v for s, v in zip(sums, rgb)]
            count += 1
    return [s / max(count, 1) for s in sums]


def png_scalars(*paths):
    """The colour arrays of PNG files."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    images = []
    for path in paths:
        reader = vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        images.append(reader.GetOutput().GetPointData().GetScalars())
    return images


def pixels_apart(path_a, path_b, threshold):
    """How many pixels of two PNGs of the same size have a channel that differs by at least
    threshold (of 255)."""
    a, b = png_scalars(path_a, path_b)
    if a.GetNumberOfTuples() != b.GetNumberOfTuples():
        return a.GetNumberOfTuples()
    components = a.GetNumberOfComponents()
    return sum(1 for i in range(a.GetNumberOfTuples())
               if any(abs(a.GetComponent(i, c) - b.GetComponent(i, c)) >= threshold
                      for c in range(components)))


def image_difference(path_a, path_b):
    """Mean absolute per-channel difference of two PNGs of the same size, in [0, 255]."""
    a, b = png_scalars(path_a, path_b)
    if a.GetNumberOfValues() != b.GetNumberOfValues():
        return float("inf")
    n = a.GetNumberOfValues()
    return sum(abs(a.GetValue(i) - b.GetValue(i)) for i in range(n)) / n


def free_port():
    """A TCP port of 127.0.0.1 free now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(port, process, seconds=60):
    """Whether a server process listens on the port within the time."""
    deadline = time.time() + seconds
    while time.time() < deadline and process.poll() is None:
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return True
        time.sleep(0.5)
    return False


def write_image(path, dimensions, values, spacing=(1, 1, 1), array_type="vtkFloatArray"):
    """Write a .vti of `dimensions` points whose point scalars "scalars" (a VTK array class
    name) hold values (x fastest)."""
    from vtkmodules import vtkCommonCore
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    image = vtkImageData()
    image.SetDimensions(*dimensions)
    image.SetSpacing(*spacing)
    array = getattr(vtkCommonCore, array_type)()
    array.SetName("scalars")
    for v in values:
        array.InsertNextValue(v)
    image.GetPointData().SetScalars(array)
    writer = vtkXMLImageDataWriter()
    writer.SetInputData(image)
    writer.SetFileName(path)
    writer.Write()


def environment_for_mpiexec():
    """This process's environment without the variables of an MPI job: pvpython may have
    started MPI as a singleton, and they would make a child mpiexec think it runs inside a
    job."""
    return {k: v for k, v in os.environ.items()
            if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_"))}


@contextlib.contextmanager
def pvserver_session(command, plugin, ns, log=subprocess.DEVNULL):
    """Start `command` (a pvserver command line, perhaps under mpiexec) on a free port of
    127.0.0.1 and connect to it with the plugin loaded on both sides (its proxies into ns).
    Yields the port, or None when the server did not listen; disconnects and stops the
    server at the end."""
    from paraview.simple import Connect, Disconnect, LoadPlugin
    port = free_port()
    server = subprocess.Popen(command + ["--server-port=%d" % port, "--hostname=127.0.0.1"],
                              stdout=log, stderr=subprocess.STDOUT,
                              env=environment_for_mpiexec())
    try:
        if not wait_for(port, server):
            yield None
        else:
            Connect("127.0.0.1", port)
            LoadPlugin(plugin, remote=True, ns=ns)
            LoadPlugin(plugin, remote=False, ns=ns)
            yield port
            Disconnect()
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()


def run_gui_script(paraview, script, env, result_file):
    """Runs a script in the real paraview GUI (paraview --script, under a display) and
    returns the "name value" lines it wrote to result_file as a dict; exits with a failure
    when paraview does not exit within 300 s or the script wrote nothing."""
    if os.path.exists(result_file):
        os.remove(result_file)
    # The GUI runs the script without __file__: it finds these helpers on PYTHONPATH.
    here = os.path.dirname(os.path.abspath(__file__))
    env = dict(env, PYTHONPATH=os.pathsep.join(p for p in (here, env.get("PYTHONPATH")) if p))
    try:
        subprocess.run([paraview, "--dr", "--script=" + script], env=env, timeout=300)
    except subprocess.TimeoutExpired:
        print("FAIL  paraview did not exit within 300 s")
        sys.exit(1)
    if not os.path.exists(result_file):
        print("FAIL  the GUI script wrote no result")
        sys.exit(1)
    return dict(line.split(" ", 1) for line in open(result_file).read().splitlines() if line)


def finish(failures):
    """Report and exit. The process leaves through os._exit: ParaView 5.11 tearing down
    its render views at interpreter exit under Xvfb can raise a GLXBadContext X error
    (ParaView's own Volume representation too), which would turn a passing test red."""
    for failure in failures:
        print("FAIL  " + failure)
    print("%d check(s) failed" % len(failures) if failures else "all checks passed")
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(1 if failures else 0)
