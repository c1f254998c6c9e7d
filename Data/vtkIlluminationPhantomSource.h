/**
 * @class vtkIlluminationPhantomSource
 * @brief Procedural volumes for illumination tests, benchmarks and the demo.
 *
 * Scenes (point scalars "Density", spacing 1, origin 0):
 * - ThreeSpheres: three spheres of value 200 in an empty (0) box, arranged as in Fig. 7 of
 *   the selective-light-updates paper (unsigned char).
 * - Slab: a homogeneous slab of value 1 over the whole x-y extent between the z indices
 *   SlabBegin and SlabEnd (inclusive), 0 elsewhere (float), for analytic tests.
 * - CTPhantom: a CT-like head: a skull shell (600), soft tissue (300), two low-density
 *   ventricles (100) and a
 *   few dense inclusions (1000) (unsigned short).
 * - Chirp: the test scene of Fig. 4 of the filtered-shadows paper: an opaque floor (value 1,
 *   the lowest 3 z layers) under an occluder layer (z from 60 % to 75 % of the height)
 *   whose value is a chirp along x, 0.5 (1 + cos(phase)), its frequency rising from 1/40
 *   to 1/4 cycle per voxel (float).
 * Cost: one pass over the points.
 */
#ifndef vtkIlluminationPhantomSource_h
#define vtkIlluminationPhantomSource_h

#include "VolIllumDataModule.h"
#include "vtkImageAlgorithm.h"

class VOLILLUMDATA_EXPORT vtkIlluminationPhantomSource : public vtkImageAlgorithm
{
public:
  static vtkIlluminationPhantomSource* New();
  vtkTypeMacro(vtkIlluminationPhantomSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Scenes
  {
    ThreeSpheres = 0,
    Slab = 1,
    CTPhantom = 2,
    Chirp = 3
  };

  ///@{
  /** Which scene to generate. Default ThreeSpheres. */
  vtkSetClampMacro(Scene, int, ThreeSpheres, Chirp);
  vtkGetMacro(Scene, int);
  ///@}

  ///@{
  /** Number of points along each axis (2 to 1024). Default 64^3. */
  vtkSetVector3Macro(Dimensions, int);
  vtkGetVector3Macro(Dimensions, int);
  ///@}

  ///@{
  /** First and last z index of the slab scene. Defaults 16 and 47. */
  vtkSetMacro(SlabBegin, int);
  vtkGetMacro(SlabBegin, int);
  vtkSetMacro(SlabEnd, int);
  vtkGetMacro(SlabEnd, int);
  ///@}

protected:
  vtkIlluminationPhantomSource();
  ~vtkIlluminationPhantomSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Scene = ThreeSpheres;
  int Dimensions[3] = { 64, 64, 64 };
  int SlabBegin = 16;
  int SlabEnd = 47;

private:
  vtkIlluminationPhantomSource(const vtkIlluminationPhantomSource&) = delete;
  void operator=(const vtkIlluminationPhantomSource&) = delete;
};

#endif
