/**
 * @class pqIlluminationLightingBehavior
 * @brief The GUI's side of background lighting: no render waits for the illumination.
 *
 * Started with the plugin in the paraview client (an auto-start of the plugin), it
 *  - turns AsynchronousLighting on for every representation that has it (the Illuminated
 *    Volume representations; pvpython and pvbatch leave it off),
 *  - 100 ms after the last render of a view, and every 100 ms while a computation runs,
 *    polls the IlluminationStatus proxy of each server (vtkIlluminationStatus, which lives
 *    where the views render, so this works in client-server sessions too), as ParaView's
 *    pqViewStreamingBehavior polls streaming views: when illuminations were published since
 *    the last poll, or a lighting the user cancelled has stopped, it renders the render views,
 *  - shows the computation in ParaView's progress bar without blocking input, and cancels
 *    it when the progress bar's abort is pressed,
 *  - gives the illumination filters' Lights the lights table's layout: a list of 14
 *    numbers a light that a filter is loaded or created with (state files and scripts
 *    written before the radius column) becomes 15 a light with radius 0, as the server
 *    reads it, so that the table shows and edits the lights it holds.
 */
#ifndef pqIlluminationLightingBehavior_h
#define pqIlluminationLightingBehavior_h

#include <QMap>
#include <QObject>
#include <QPointer>
#include <QTimer>

#include "vtkSmartPointer.h"

class pqPipelineSource;
class pqRepresentation;
class pqServer;
class pqView;
class vtkSMProxy;

class pqIlluminationLightingBehavior : public QObject
{
  Q_OBJECT

public:
  explicit pqIlluminationLightingBehavior(QObject* parent = nullptr);
  ~pqIlluminationLightingBehavior() override;

  void startup();
  void shutdown();

private Q_SLOTS:
  void onServerRemoved(pqServer* server);
  void onRepresentationAdded(pqRepresentation* representation);
  void onViewAdded(pqView* view);
  void onSourceAdded(pqPipelineSource* source);
  void poll();
  void cancel();

private:
  void showProgress(bool busy, double progress);
  void renderViews();
  /// The server's IlluminationStatus proxy (nullptr before the plugin's proxies are defined).
  vtkSMProxy* status(pqServer* server);

  QMap<pqServer*, vtkSmartPointer<vtkSMProxy>> Status;
  QTimer Timer;
  bool ShowingProgress = false;
  bool PreviousUnblock = false;
  unsigned int Publications = 0; // results published, as of the last poll
  bool Cancelled = false;        // the user cancelled a lighting that has not stopped yet
};

#endif
