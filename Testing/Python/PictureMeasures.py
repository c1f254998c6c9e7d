"""Measures of rendered pictures shared by the picture tests: grain (relative high-pass
energy, mean |luminance - its 3x3 median| / mean luminance) and brightness over a mask."""
import numpy


def rgb(path):
    """A PNG as a float array (rows, columns, 3)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    columns, rows, _ = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float)
    return values.reshape(rows, columns, -1)[:, :, :3]


def luminance(image):
    return image @ numpy.array([0.2126, 0.7152, 0.0722])


def erode(mask, pixels):
    """The mask without its outer pixels (and the image border), pixels times."""
    for _ in range(pixels):
        inner = mask.copy()
        inner[1:, :] &= mask[:-1, :]
        inner[:-1, :] &= mask[1:, :]
        inner[:, 1:] &= mask[:, :-1]
        inner[:, :-1] &= mask[:, 1:]
        inner[[0, -1], :] = False
        inner[:, [0, -1]] = False
        mask = inner
    return mask


def median3x3(values):
    rows, columns = values.shape
    padded = numpy.pad(values, 1, mode="edge")
    shifted = [padded[i:i + rows, j:j + columns] for i in range(3) for j in range(3)]
    return numpy.median(numpy.stack(shifted), axis=0)


def high_pass(values, mask):
    """Relative high-pass energy of a luminance image over a mask."""
    return numpy.abs(values - median3x3(values))[mask].mean() / values[mask].mean()
