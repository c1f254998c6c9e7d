/**
 * @class pqIlluminationTransferFunctionWidget
 * @brief Panel widget of the illumination filters' transfer-function properties.
 *
 * A drop-down of the session's colour maps (for ColorTransferFunction) or opacity
 * functions (for OpacityFunction) by name ("DensityLUT", "DensityPWF"), plus "None" (the
 * filters' grey default ramp). A filter created in the GUI starts with the colour map
 * and opacity function of its Scalars array: the ones the colour map editor shows for that
 * array, so the lighting is computed with the transfer functions the user sees.
 */
#ifndef pqIlluminationTransferFunctionWidget_h
#define pqIlluminationTransferFunctionWidget_h

#include "pqPropertyWidget.h"
#include "pqSMProxy.h"
#include "vtkSmartPointer.h"

#include <QString>

#include <vector>

class QComboBox;
class vtkSMProxy;

class pqIlluminationTransferFunctionWidget : public pqPropertyWidget
{
  Q_OBJECT
  Q_PROPERTY(pqSMProxy chosenFunction READ chosenFunction WRITE setChosenFunction)
  typedef pqPropertyWidget Superclass;

public:
  pqIlluminationTransferFunctionWidget(
    vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent = nullptr);
  ~pqIlluminationTransferFunctionWidget() override;

  /// The transfer function chosen (nullptr for None).
  pqSMProxy chosenFunction() const;
  void setChosenFunction(pqSMProxy function);

Q_SIGNALS:
  void chosenFunctionChanged();

private:
  Q_DISABLE_COPY(pqIlluminationTransferFunctionWidget)

  /// The function of the filter's Scalars array (created if the session has none yet).
  vtkSMProxy* ArrayFunction(vtkSMProxy* filter, bool opacity) const;

  QComboBox* Choices;
  QString Group;                                      // proxy group of the functions listed
  std::vector<vtkSmartPointer<vtkSMProxy>> Functions; // one per entry; entry 0 is None
};

#endif
