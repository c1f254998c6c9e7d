#include "pqIlluminationTransferFunctionWidget.h"

#include "pqApplicationCore.h"
#include "pqProxy.h"
#include "pqServerManagerModel.h"
#include "vtkNew.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMProxyIterator.h"
#include "vtkSMSessionProxyManager.h"
#include "vtkSMTransferFunctionManager.h"

#include <QComboBox>
#include <QHBoxLayout>
#include <QTimer>

#include <cstring>

//------------------------------------------------------------------------------
pqIlluminationTransferFunctionWidget::pqIlluminationTransferFunctionWidget(
  vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent)
  : Superclass(proxy, parent)
  , Choices(new QComboBox(this))
{
  this->setShowLabel(true);
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(this->Choices);

  const bool opacity = std::strstr(property->GetXMLName(), "Opacity") != nullptr;
  this->Choices->addItem(tr("None (grey ramp over the scalar range)"));
  this->Functions.emplace_back(nullptr);
  vtkSMSessionProxyManager* pxm = proxy->GetSessionProxyManager();

  vtkNew<vtkSMProxyIterator> it;
  it->SetSessionProxyManager(pxm);
  it->SetModeToOneGroup();
  this->Group = opacity ? "piecewise_functions" : "lookup_tables";
  for (it->Begin(this->Group.toUtf8().data()); !it->IsAtEnd(); it->Next())
  {
    this->Choices->addItem(QString::fromUtf8(it->GetKey()));
    this->Functions.emplace_back(it->GetProxy());
  }
  this->setChosenFunction(vtkSMPropertyHelper(property).GetAsProxy());

  this->addPropertyLink(this, "chosenFunction", SIGNAL(chosenFunctionChanged()), property);
  QObject::connect(this->Choices, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
    &pqIlluminationTransferFunctionWidget::chosenFunctionChanged);

  // A filter not applied yet starts with the function of its Scalars array. ParaView marks
  // a new filter as not applied only after its panel is built: decide once that is done.
  QTimer::singleShot(0, this,
    [this, proxy, opacity]()
    {
      pqProxy* item =
        pqApplicationCore::instance()->getServerManagerModel()->findItem<pqProxy*>(proxy);
      if (!item || item->modifiedState() != pqProxy::UNINITIALIZED || this->chosenFunction())
      {
        return;
      }
      if (vtkSMProxy* function = this->ArrayFunction(proxy, opacity))
      {
        this->setChosenFunction(function);
        Q_EMIT this->chosenFunctionChanged();
      }
    });
}

//------------------------------------------------------------------------------
pqIlluminationTransferFunctionWidget::~pqIlluminationTransferFunctionWidget() = default;

//------------------------------------------------------------------------------
vtkSMProxy* pqIlluminationTransferFunctionWidget::ArrayFunction(
  vtkSMProxy* filter, bool opacity) const
{
  if (!filter->GetProperty("SelectInputScalars"))
  {
    return nullptr;
  }
  const char* array = vtkSMPropertyHelper(filter, "SelectInputScalars").GetAsString(4);
  if (!array || !*array)
  {
    return nullptr;
  }
  vtkNew<vtkSMTransferFunctionManager> manager;
  vtkSMSessionProxyManager* pxm = filter->GetSessionProxyManager();
  return opacity ? manager->GetOpacityTransferFunction(array, pxm)
                 : manager->GetColorTransferFunction(array, pxm);
}

//------------------------------------------------------------------------------
pqSMProxy pqIlluminationTransferFunctionWidget::chosenFunction() const
{
  const int index = this->Choices->currentIndex();
  return index > 0 ? pqSMProxy(this->Functions[index].Get()) : pqSMProxy();
}

//------------------------------------------------------------------------------
void pqIlluminationTransferFunctionWidget::setChosenFunction(pqSMProxy function)
{
  for (size_t i = 0; i < this->Functions.size(); ++i)
  {
    if (this->Functions[i].Get() == function.GetPointer())
    {
      this->Choices->setCurrentIndex(static_cast<int>(i));
      return;
    }
  }
  // A function registered after the list was made.
  const char* name = function ? function->GetSessionProxyManager()->GetProxyName(
                                  this->Group.toUtf8().data(), function.GetPointer())
                              : nullptr;
  this->Choices->addItem(name ? QString::fromUtf8(name) : tr("(unnamed)"));
  this->Functions.emplace_back(function.GetPointer());
  this->Choices->setCurrentIndex(static_cast<int>(this->Functions.size() - 1));
}
