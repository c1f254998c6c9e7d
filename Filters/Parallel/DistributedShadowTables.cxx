#include "DistributedShadowTables.h"

#include "ImageExtents.h"
#include "ParallelCollectives.h"
#include "vtkMultiProcessController.h"

#include <algorithm>
#include <cmath>

namespace volillum
{

namespace
{
// Messages of the cells beyond a window (ShareCellsBeyond).
constexpr int CellsBeyondTag = 8280;

// Collective: the tables read, 4 values a key: spherical (1) or not, the table, the axis and
// the sign toward the light; the first process with a piece (`root`) decides.
std::vector<int> AgreeOnTableKeys(vtkMultiProcessController* controller, int root,
  const std::vector<ShadowLookup>& lookups, const std::vector<SphericalLookup>& sphericalLookups)
{
  std::vector<int> keys;
  for (const auto& l : lookups)
  {
    bool known = false;
    for (size_t k = 0; k < keys.size(); k += 4)
    {
      known = known ||
        (keys[k + 1] == static_cast<int>(l.Table) && keys[k + 2] == l.Axis &&
          keys[k + 3] == l.Sign);
    }
    if (!known)
    {
      keys.insert(keys.end(), { 0, static_cast<int>(l.Table), l.Axis, l.Sign });
    }
  }
  for (const auto& l : sphericalLookups)
  {
    keys.insert(keys.end(), { 1, static_cast<int>(l.Table), 2, -1 });
  }
  int count = static_cast<int>(keys.size());
  controller->Broadcast(&count, 1, root);
  keys.resize(count);
  if (count > 0)
  {
    controller->Broadcast(keys.data(), count, root);
  }
  return keys;
}

// Collective: every process's window (first cells, then cell counts; zeros for none).
std::vector<int> GatherWindows(vtkMultiProcessController* controller, const TableWindow* own)
{
  int window[6] = { 0, 0, 0, 0, 0, 0 };
  if (own)
  {
    std::copy(own->First.begin(), own->First.end(), window);
    std::copy(own->N.begin(), own->N.end(), window + 3);
  }
  std::vector<int> windows(6 * static_cast<size_t>(controller->GetNumberOfProcesses()));
  controller->AllGather(window, windows.data(), 6);
  return windows;
}

// The columns of one table that the processes' windows (`windows`, first cell and cell
// counts, 6 values a process) share, along `axis` toward `sign`.
struct SharedColumns
{
  const std::vector<int>& Windows;
  int Axis;
  int Sign;
  int U;
  int V;

  // The columns (u, v) that the windows of p and q share, in w; whether there are any.
  bool Shared(int p, int q, TableWindow& w) const
  {
    for (int a : { this->U, this->V })
    {
      const int* wp = &this->Windows[6 * p];
      const int* wq = &this->Windows[6 * q];
      const int first = std::max(wp[a], wq[a]);
      const int end = std::min(wp[a] + wp[3 + a], wq[a] + wq[3 + a]);
      w.First[a] = first;
      w.N[a] = std::max(0, end - first);
    }
    return w.N[this->U] > 0 && w.N[this->V] > 0;
  }

  // The processes with windows (`tableExtents` not empty) whose columns and this process's
  // (`local`) meet, where one of them has cells beyond the other's toward the light.
  std::vector<int> Peers(int local, const std::vector<int>& tableExtents) const
  {
    std::vector<int> peers;
    TableWindow common;
    for (int q = 0; 6 * static_cast<size_t>(q) < tableExtents.size(); ++q)
    {
      if (q != local && ExtentPoints(&tableExtents[6 * q]) > 0 && this->Shared(local, q, common) &&
        (this->Upwind(q, local) || this->Upwind(local, q)))
      {
        peers.push_back(q);
      }
    }
    return peers;
  }

  // Whether the window of q has cells beyond the window of p's first cell toward the light
  // along the axis (sign > 0: a higher index), where p's grown block ends on a column: only
  // then can it send p cells beyond that.
  bool Upwind(int q, int p) const
  {
    const int* wq = &this->Windows[6 * q];
    const int* wp = &this->Windows[6 * p];
    return this->Sign > 0 ? wq[this->Axis] + wq[3 + this->Axis] - 1 > wp[this->Axis]
                          : wq[this->Axis] < wp[this->Axis] + wp[3 + this->Axis] - 1;
  }
};

// Sums received from another process over the columns w, added into this window's `total`.
void AddReceived(const std::vector<double>& sums, const TableWindow& w, const TableWindow& own,
  int channels, int u, int v, std::vector<double>& total)
{
  for (int j = 0; j < w.N[v]; ++j)
  {
    const double* in = sums.data() + static_cast<size_t>(channels) * j * w.N[u];
    double* out = total.data() +
      static_cast<size_t>(channels) *
        ((w.First[v] - own.First[v] + j) * own.N[u] + w.First[u] - own.First[u]);
    for (int i = 0; i < channels * w.N[u]; ++i)
    {
      out[i] += in[i];
    }
  }
}
}

//------------------------------------------------------------------------------
void GrownBlock(const GridGeometry& target, const VolumePiece& piece, const int own[6],
  double reach, double margin, int tables[6], int wanted[6])
{
  const GridGeometry& data = piece.Whole;
  for (int a = 0; a < 3; ++a)
  {
    const double u[2] = { (target.Origin[a] + own[2 * a] * target.Spacing[a] - data.Origin[a]) /
        data.Spacing[a],
      (target.Origin[a] + own[2 * a + 1] * target.Spacing[a] - data.Origin[a]) / data.Spacing[a] };
    const double spacing = std::abs(data.Spacing[a]);
    const int halo = static_cast<int>(std::ceil(reach / spacing)) + 1;
    const int more = margin > 0.0 ? static_cast<int>(std::ceil(margin / spacing)) + 1 : 0;
    const int first = std::min(piece.FirstCell[a], static_cast<int>(std::floor(u[0])));
    const int last = std::max(piece.LastCell[a] + 1, static_cast<int>(std::ceil(u[1])));
    tables[2 * a] = std::max(0, first - halo);
    tables[2 * a + 1] = std::min(data.Dimensions[a] - 1, last + halo);
    wanted[2 * a] = std::max(0, tables[2 * a] - more);
    wanted[2 * a + 1] = std::min(data.Dimensions[a] - 1, tables[2 * a + 1] + more);
  }
}

//------------------------------------------------------------------------------
long long ShareCellsBeyond(vtkMultiProcessController* controller, const VolumePiece& piece,
  const std::vector<ShadowLookup>& lookups, const std::vector<SphericalLookup>& sphericalLookups,
  int channels, const std::vector<int>& tableExtents, std::vector<CartesianSAT>& tables,
  std::vector<SphericalSAT>& spherical)
{
  const int processes = controller->GetNumberOfProcesses();
  const int local = controller->GetLocalProcessId();
  int root = 0;
  while (root < processes - 1 && ExtentPoints(&tableExtents[6 * root]) <= 0)
  {
    ++root;
  }
  const std::vector<int> keys = AgreeOnTableKeys(controller, root, lookups, sphericalLookups);
  const bool lit = ExtentPoints(&tableExtents[6 * local]) > 0;
  long long sent = 0;
  for (size_t k = 0; k < keys.size(); k += 4)
  {
    const bool isSpherical = keys[k] == 1;
    const size_t table = static_cast<size_t>(keys[k + 1]);
    const int axis = keys[k + 2], sign = keys[k + 3];
    // Every process's window of the table.
    const TableWindow* own = nullptr;
    if (lit)
    {
      own = isSpherical ? &spherical[table].GetWindow() : &tables[table].GetWindow();
    }
    const std::vector<int> windows = GatherWindows(controller, own);
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const SharedColumns columns{ windows, axis, sign, u, v };
    const std::vector<int> peers = lit ? columns.Peers(local, tableExtents) : std::vector<int>();
    std::vector<double> total(lit ? static_cast<size_t>(channels) * own->N[u] * own->N[v] : 0, 0.0);
    std::vector<double> sums;
    WithEachPeer(local, peers,
      [&](size_t m, bool send)
      {
        const int q = peers[m];
        TableWindow w;
        if (!columns.Upwind(send ? local : q, send ? q : local) || !columns.Shared(local, q, w))
        {
          return;
        }
        sums.assign(static_cast<size_t>(channels) * w.N[u] * w.N[v], 0.0);
        const vtkIdType size = static_cast<vtkIdType>(sums.size());
        if (!send)
        {
          controller->Receive(sums.data(), size, q, CellsBeyondTag);
          AddReceived(sums, w, *own, channels, u, v, total);
          return;
        }
        // The other's grown block: its cells' points (the window's process's table extent).
        const int* e = &tableExtents[6 * q];
        VolumePiece other;
        other.Whole = piece.Whole;
        for (int a = 0; a < 3; ++a)
        {
          other.Offset[a] = other.FirstCell[a] = e[2 * a];
          other.LastCell[a] = e[2 * a + 1] - 1;
        }
        if (isSpherical)
        {
          spherical[table].AddCellsBeyond(piece, other, w, sums.data());
        }
        else
        {
          tables[table].AddCellsBeyond(piece, other, w, axis, sign, sums.data());
        }
        controller->Send(sums.data(), size, q, CellsBeyondTag);
        sent += size * static_cast<long long>(sizeof(double));
      });
    if (lit && isSpherical)
    {
      spherical[table].SetBeyond(total.data());
    }
    else if (lit)
    {
      tables[table].SetBeyond(axis, sign, total.data());
    }
  }
  return sent;
}

}
