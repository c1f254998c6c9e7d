#include "pqIlluminationLightingBehavior.h"

#include "IlluminationLights.h"

#include "pqApplicationCore.h"
#include "pqPipelineSource.h"
#include "pqProgressManager.h"
#include "pqRenderView.h"
#include "pqRepresentation.h"
#include "pqServer.h"
#include "pqServerManagerModel.h"
#include "vtkSMDoubleVectorProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMProxyManager.h"
#include "vtkSMSessionProxyManager.h"

#include <algorithm>
#include <vector>

namespace
{
constexpr int PollMilliseconds = 100;
}

//------------------------------------------------------------------------------
pqIlluminationLightingBehavior::pqIlluminationLightingBehavior(QObject* parent)
  : QObject(parent)
{
  this->Timer.setSingleShot(true);
  this->Timer.setInterval(PollMilliseconds);
  QObject::connect(&this->Timer, &QTimer::timeout, this, &pqIlluminationLightingBehavior::poll);
}

//------------------------------------------------------------------------------
pqIlluminationLightingBehavior::~pqIlluminationLightingBehavior() = default;

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::startup()
{
  pqApplicationCore* core = pqApplicationCore::instance();
  if (!core)
  {
    return;
  }
  pqServerManagerModel* model = core->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::aboutToRemoveServer, this,
    &pqIlluminationLightingBehavior::onServerRemoved);
  QObject::connect(model, &pqServerManagerModel::representationAdded, this,
    &pqIlluminationLightingBehavior::onRepresentationAdded);
  QObject::connect(
    model, &pqServerManagerModel::viewAdded, this, &pqIlluminationLightingBehavior::onViewAdded);
  QObject::connect(model, &pqServerManagerModel::sourceAdded, this,
    &pqIlluminationLightingBehavior::onSourceAdded);
  QObject::connect(core->getProgressManager(), &pqProgressManager::abort, this,
    &pqIlluminationLightingBehavior::cancel);
  // The plugin may be loaded after the session started.
  for (pqView* view : model->findItems<pqView*>())
  {
    this->onViewAdded(view);
  }
  for (pqRepresentation* representation : model->findItems<pqRepresentation*>())
  {
    this->onRepresentationAdded(representation);
  }
  for (pqPipelineSource* source : model->findItems<pqPipelineSource*>())
  {
    this->onSourceAdded(source);
  }
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::onSourceAdded(pqPipelineSource* source)
{
  // An illumination filter's Lights (rows of LightParameterCount numbers) as a state file
  // or a script's constructor gave them, before the source was added: a list of 14 numbers
  // a light gains radius 0 after each light. (A list set later keeps its layout in the GUI;
  // the server reads both.)
  vtkSMProxy* proxy = source->getProxy();
  auto* lights = vtkSMDoubleVectorProperty::SafeDownCast(proxy->GetProperty("Lights"));
  const int count = lights ? static_cast<int>(lights->GetNumberOfElements()) : 0;
  if (!lights || lights->GetNumberOfElementsPerCommand() != volillum::LightParameterCount ||
    volillum::LightParametersPerLight(count) != volillum::LegacyLightParameterCount)
  {
    return;
  }
  std::vector<double> padded;
  for (int i = 0; i < count; ++i)
  {
    padded.push_back(lights->GetElement(i));
    if (i % volillum::LegacyLightParameterCount == volillum::LegacyLightParameterCount - 1)
    {
      padded.push_back(0.0);
    }
  }
  lights->SetElements(padded.data(), static_cast<unsigned int>(padded.size()));
  proxy->UpdateVTKObjects();
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::shutdown()
{
  this->Timer.stop();
  this->showProgress(false, 1.0);
  this->Status.clear();
}

//------------------------------------------------------------------------------
vtkSMProxy* pqIlluminationLightingBehavior::status(pqServer* server)
{
  // Made when first needed: the plugin starts before its proxies are defined.
  auto found = this->Status.find(server);
  if (found != this->Status.end())
  {
    return found.value();
  }
  vtkSMSessionProxyManager* pxm = server->proxyManager();
  vtkSmartPointer<vtkSMProxy> proxy;
  if (pxm && pxm->GetPrototypeProxy("misc", "IlluminationStatus"))
  {
    proxy.TakeReference(pxm->NewProxy("misc", "IlluminationStatus"));
    proxy->UpdateVTKObjects();
    this->Status.insert(server, proxy);
  }
  return proxy;
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::onServerRemoved(pqServer* server)
{
  this->Status.remove(server);
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::onRepresentationAdded(pqRepresentation* representation)
{
  vtkSMProxy* proxy = representation ? representation->getProxy() : nullptr;
  if (proxy && proxy->GetProperty("AsynchronousLighting"))
  {
    vtkSMPropertyHelper(proxy, "AsynchronousLighting").Set(1);
    proxy->UpdateVTKObjects();
  }
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::onViewAdded(pqView* view)
{
  if (qobject_cast<pqRenderView*>(view))
  {
    // Polled 100 ms after the last render: renders in quick succession (a camera drag) ask
    // nothing of the server.
    QObject::connect(view, &pqView::endRender, &this->Timer, QOverload<>::of(&QTimer::start));
  }
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::poll()
{
  bool busy = false;
  unsigned int publications = 0;
  double progress = 1.0;
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqServer* server : model->findItems<pqServer*>())
  {
    vtkSMProxy* status = this->status(server);
    if (!status)
    {
      continue;
    }
    status->UpdatePropertyInformation();
    busy = busy || vtkSMPropertyHelper(status, "IlluminationBusy").GetAsInt() != 0;
    publications += vtkSMPropertyHelper(status, "IlluminationPublications").GetAsInt();
    progress =
      std::min(progress, vtkSMPropertyHelper(status, "IlluminationProgress").GetAsDouble());
  }
  this->showProgress(busy, progress);
  // A render draws what was published since the last poll, or, once a lighting the user
  // cancelled has stopped, the last finished illumination again.
  const bool published = publications != this->Publications;
  const bool cancelled = this->Cancelled && !busy;
  this->Publications = publications;
  this->Cancelled = this->Cancelled && busy;
  if (published || cancelled)
  {
    this->renderViews(); // their ends poll again
  }
  else if (busy || this->ShowingProgress)
  {
    this->Timer.start();
  }
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::cancel()
{
  if (!this->ShowingProgress)
  {
    return; // another operation's abort
  }
  for (pqServer* server : this->Status.keys())
  {
    this->Status.value(server)->InvokeCommand("CancelIllumination");
  }
  this->Cancelled = true;
  this->Timer.start(); // renders once the lighting has stopped
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::renderViews()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  for (pqRenderView* view : model->findItems<pqRenderView*>())
  {
    view->render();
  }
}

//------------------------------------------------------------------------------
void pqIlluminationLightingBehavior::showProgress(bool busy, double progress)
{
  // While another object holds the progress manager, it ignores everyone else's calls: the
  // bar is shown or taken down only when it is free, so that every call counts and pairs.
  pqProgressManager* manager = pqApplicationCore::instance()->getProgressManager();
  if (manager->isLocked())
  {
    return;
  }
  if (busy && !this->ShowingProgress)
  {
    // The progress bar with its abort button, without the input blocking ParaView applies
    // while a pipeline update runs on the GUI's thread: this one runs beside it.
    manager->setEnableProgress(true);
    this->PreviousUnblock = manager->unblockEvents(true);
    manager->setEnableAbort(true);
    this->ShowingProgress = true;
  }
  if (busy)
  {
    manager->setProgress(QString("Illuminating the volume"), static_cast<int>(100.0 * progress));
  }
  else if (this->ShowingProgress)
  {
    manager->setEnableAbort(false);
    manager->setEnableProgress(false);
    manager->unblockEvents(this->PreviousUnblock);
    this->ShowingProgress = false;
  }
}
