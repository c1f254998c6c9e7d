"""An image with a direction matrix is lit and rendered in its own frame.

  TestRotatedImage.py CLI OUTPUT_DIR

A ball of density (rotation-invariant) is written twice: axis-aligned, and with a
direction matrix that turns it 45 degrees about z. Both are lit by the same world-space
light from +x and rendered from the same side: the pictures must agree (image RMS below
2 %), and the lit side must face +x (the brightness-weighted centre of the ball lies to the
right of its centre). Before images were lit in their own frame, the rotated ball was lit
from 45 degrees below +x.
"""
import json
import os
import subprocess
import sys

import numpy
from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

here = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [here, os.path.join(here, "..", "..", "..", "Testing", "Python")]
from PictureMeasures import rgb  # noqa: E402
from TestImageFidelity import rms  # noqa: E402


def write_ball(path, direction):
    n = 33
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    image.SetDirectionMatrix(*direction)
    values = vtkFloatArray()
    values.SetName("density")
    c = (n - 1) / 2.0
    for k in range(n):
        for j in range(n):
            for i in range(n):
                r = ((i - c) ** 2 + (j - c) ** 2 + (k - c) ** 2) ** 0.5
                values.InsertNextValue(max(0.0, min(1.0, 11.0 - r)) * 100.0)
    image.GetPointData().SetScalars(values)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.SetDataModeToBinary()
    writer.Write()


def main():
    cli, out = sys.argv[1], sys.argv[2]
    settings = os.path.join(out, "rotated.json")
    with open(settings, "w") as f:
        json.dump({"image_size": [200, 200], "camera": {"azimuth": 0, "elevation": 0},
                   "lights": [{"type": "directional", "position": [1, 0, 0],
                               "focal_point": [0, 0, 0]}]}, f)
    s = 0.5 ** 0.5
    pictures = []
    for name, direction in (("straight", (1, 0, 0, 0, 1, 0, 0, 0, 1)),
                            ("rotated", (s, -s, 0, s, s, 0, 0, 0, 1))):
        volume = os.path.join(out, "ball-%s.vti" % name)
        picture = os.path.join(out, "ball-%s.png" % name)
        write_ball(volume, direction)
        run = subprocess.run([cli, volume, "--config", settings, "--output", picture],
                             capture_output=True, text=True, timeout=300)
        if run.returncode != 0:
            sys.stderr.write(run.stdout + run.stderr)
            print("FAILED: volillum-render exited with %d" % run.returncode)
            return 1
        pictures.append(rgb(picture))
    difference = rms(pictures[1], pictures[0])
    brightness = pictures[1].sum(axis=2)
    columns = numpy.arange(brightness.shape[1])
    covered = brightness > 6
    centre = columns[covered.any(axis=0)].mean()
    weighted = (brightness * columns).sum() / brightness.sum()
    print("rotated vs axis-aligned image RMS %.2f %% (bound 2 %%); lit side %.1f pixels right of "
          "the ball's centre" % (difference, weighted - centre))
    ok = difference <= 2.0 and weighted - centre > 3.0
    print("ok" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
