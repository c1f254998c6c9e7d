"""Rendered-image fidelity: images lit by Multi-Light Illumination Volume and by Filtered
Volumetric Shadows (FilterWidth 0), both at ResolutionScale 0.5, against the image lit by
the ray-marched reference at scale 1; same view, transfer function and lights (a
directional, a point and a spot light together).

  TestImageFidelity.py CLI OUTPUT_DIR SCENE BOUND [VOLUME]

SCENE is slab or spheres (generated phantoms) or a name for VOLUME. The measure is the one
of Table 2 of the unstructured-grid paper: the root mean square of the pixel differences
over all pixels and colour channels, in per cent of the value range (255). The RMS over the
pixels the object covers, the difference of the image lit by the reference itself at scale
0.5 (the floor any method at that scale meets: the exact illumination at the coarse points,
interpolated by the renderer) and that of the local-shading image of the same view (what the
illumination changes) are printed beside it. Fails when either method's image RMS
exceeds BOUND (per cent).
"""
import json
import os
import subprocess
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                "Testing", "Python"))
from PictureMeasures import rgb

LIGHTS = [
    {"type": "directional", "position": [0.15, -0.1, 1.5], "focal_point": [0.5, 0.5, 0.5],
     "relative": True, "color": [1.0, 0.9, 0.7], "intensity": 0.8},
    {"type": "point", "position": [-0.3, -0.2, 1.4], "relative": True,
     "color": [0.6, 0.8, 1.0], "intensity": 0.8},
    {"type": "spot", "position": [0.8, 1.8, 0.7], "focal_point": [0.5, 0.5, 0.5],
     "relative": True, "color": [1.0, 0.7, 0.9], "intensity": 0.8, "cone_angle": 25,
     "exponent": 2},
]


def render(cli, source, settings, output):
    path = output + ".json"
    with open(path, "w") as f:
        json.dump(settings, f)
    run = subprocess.run([cli] + source + ["--config", path, "--output", output],
                         capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        sys.stderr.write(run.stdout + run.stderr)
        raise SystemExit("FAILED: volillum-render exited with %d" % run.returncode)
    return rgb(output)


def rms(image, reference, mask=None):
    d = image - reference
    if mask is not None:
        d = d[mask]
    return 100.0 * numpy.sqrt(numpy.mean(d * d)) / 255.0


def main():
    cli, out, scene, bound = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    if scene in ("slab", "spheres"):
        source = ["--phantom", scene, "--dims", "64"]
    else:
        source = [sys.argv[5]]
    base = {"image_size": [256, 256], "lights": LIGHTS}
    prefix = os.path.join(out, "ImageFidelity-" + scene)
    both = render(cli, source, dict(base, method="reference", resolution_scale=1,
                                    side_by_side=True, labels=False), prefix + "-reference.png")
    width = both.shape[1] // 2
    local, reference = both[:, :width], both[:, width:]
    covered = reference.max(axis=2) > 2.0
    failed = False
    for method, extra in (("propagation", {}), ("filtered", {"filter_width": 0}),
                          ("reference", {})):
        image = render(cli, source, dict(base, method=method, resolution_scale=0.5, **extra),
                       "%s-%s.png" % (prefix, method))
        whole = rms(image, reference)
        if method == "reference":
            print("%-9s %-12s scale 0.5: image RMS %5.2f %%, over the object %5.2f %% (the floor: "
                  "exact illumination at the scale-0.5 points)"
                  % (scene, method, whole, rms(image, reference, covered)))
            continue
        print("%-9s %-12s scale 0.5: image RMS %5.2f %% (bound %.1f %%), over the object %5.2f %%"
              % (scene, method, whole, bound, rms(image, reference, covered)))
        failed = failed or not whole <= bound
    print("%-9s local shading only:     image RMS %5.2f %%, over the object %5.2f %% "
          "(what the illumination changes)" % (scene, rms(local, reference),
                                                  rms(local, reference, covered)))
    print("FAILED" if failed else "ok")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
