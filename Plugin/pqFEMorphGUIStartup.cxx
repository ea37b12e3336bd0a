// SPDX-License-Identifier: BSD-3-Clause
// Before any Qt header: Qt's `slots` macro would break the core headers'
// identifiers of that name.
#include "vtkFEMorphSegmentationArrays.h"

#include "pqFEMorphGUIStartup.h"

#include <pqApplicationCore.h>
#include <pqServerManagerModel.h>
#include <pqSpreadSheetView.h>
#include <pqSpreadSheetViewModel.h>
#include <pqSpreadSheetViewWidget.h>
#include <vtkSMProxy.h>
#include <vtkSMSettings.h>

#include <QHeaderView>
#include <QPointer>
#include <QStringList>

#include <algorithm>
#include <vector>

namespace
{
// Below the site (1.0) and user settings (VTK_DOUBLE_MAX) ParaView loads.
constexpr double SettingsPriority = 0.5;
// Region ids given a colour; higher ids show the colour map's NaN colour.
constexpr int MaxAnnotatedRegion = 63;

// Position of a column label in the Regions table's own order; components of
// a split array ("Axis_0", "Axis_X", "Axis_Magnitude") sort with their array.
int ColumnRank(const QString& label)
{
  const auto& columns = vtkFEMorphSegmentationArrays::RegionTableColumns();
  for (int pass = 0; pass < 2; ++pass)
  {
    QString name = label;
    if (pass == 1)
    {
      const int cut = label.lastIndexOf('_');
      if (cut <= 0)
      {
        break;
      }
      name = label.left(cut);
    }
    const auto it = std::find(columns.begin(), columns.end(), name.toStdString());
    if (it != columns.end())
    {
      return static_cast<int>(it - columns.begin());
    }
  }
  return -1;
}
} // namespace

//------------------------------------------------------------------------------
pqFEMorphGUIStartup::pqFEMorphGUIStartup(QObject* parent)
  : QObject(parent)
{
}

//------------------------------------------------------------------------------
QString pqFEMorphGUIStartup::RegionIdColorSettings()
{
  // A qualitative palette; neighbouring ids get far-apart colours.
  static const double palette[][3] = { { 0.122, 0.471, 0.706 }, { 1.000, 0.498, 0.055 },
    { 0.173, 0.627, 0.173 }, { 0.839, 0.153, 0.157 }, { 0.580, 0.404, 0.741 },
    { 0.549, 0.337, 0.294 }, { 0.890, 0.467, 0.761 }, { 0.737, 0.741, 0.133 },
    { 0.090, 0.745, 0.812 }, { 0.682, 0.780, 0.910 }, { 1.000, 0.733, 0.471 },
    { 0.596, 0.875, 0.541 } };
  const int n = static_cast<int>(sizeof(palette) / sizeof(palette[0]));
  QStringList annotations, colors;
  // -1: triangles or lines outside every region.
  annotations << "\"-1\"" << "\"none\"";
  colors << "0.6, 0.6, 0.6";
  for (int id = 0; id <= MaxAnnotatedRegion; ++id)
  {
    annotations << QString("\"%1\"").arg(id) << QString("\"%1\"").arg(id);
    const double* c = palette[id % n];
    colors << QString("%1, %2, %3").arg(c[0]).arg(c[1]).arg(c[2]);
  }
  return QString("{ \"array_lookup_tables\": { \"RegionId\": { \"PVLookupTable\": {"
                 " \"IndexedLookup\": 1, \"Annotations\": [ %1 ], \"IndexedColors\": [ %2 ]"
                 " } } } }")
    .arg(annotations.join(", "), colors.join(", "));
}

//------------------------------------------------------------------------------
void pqFEMorphGUIStartup::onStartup()
{
  vtkSMSettings::GetInstance()->AddCollectionFromString(
    RegionIdColorSettings().toStdString(), SettingsPriority);

  auto* model = pqApplicationCore::instance()->getServerManagerModel();
  QObject::connect(model, &pqServerManagerModel::viewAdded, this, &pqFEMorphGUIStartup::onViewAdded);
  for (pqView* view : model->findItems<pqView*>())
  {
    this->onViewAdded(view);
  }
}

//------------------------------------------------------------------------------
void pqFEMorphGUIStartup::onViewAdded(pqView* view)
{
  if (auto* sheet = qobject_cast<pqSpreadSheetView*>(view))
  {
    this->watch(sheet);
  }
}

//------------------------------------------------------------------------------
void pqFEMorphGUIStartup::watch(pqSpreadSheetView* view)
{
  auto* model = view->getViewModel();
  if (!model)
  {
    return;
  }
  QPointer<pqSpreadSheetView> guarded(view);
  auto reorder = [guarded]() {
    if (guarded)
    {
      orderColumns(guarded);
    }
  };
  // The model resets (and the header forgets moved sections) whenever the
  // shown data or its columns change; the header data follows.
  QObject::connect(model, &QAbstractItemModel::headerDataChanged, this, reorder);
  QObject::connect(model, &QAbstractItemModel::modelReset, this, reorder);
}

//------------------------------------------------------------------------------
void pqFEMorphGUIStartup::orderColumns(pqSpreadSheetView* view)
{
  // The view's widget holds the table (pqSpreadSheetView::createWidget).
  QWidget* container = view->widget();
  auto* widget = qobject_cast<pqSpreadSheetViewWidget*>(container);
  if (!widget && container)
  {
    widget = container->findChild<pqSpreadSheetViewWidget*>();
  }
  auto* model = view->getViewModel();
  if (!widget || !model)
  {
    return;
  }
  QHeaderView* header = widget->horizontalHeader();
  const int count = model->columnCount();
  std::vector<int> ranks(count);
  bool hasId = false, hasType = false;
  for (int c = 0; c < count; ++c)
  {
    const QString label = model->headerData(c, Qt::Horizontal, Qt::DisplayRole).toString();
    ranks[c] = ColumnRank(label);
    hasId = hasId || label == "RegionId";
    hasType = hasType || label == "TypeName";
  }
  std::vector<int> order(count);
  for (int c = 0; c < count; ++c)
  {
    order[c] = c;
  }
  if (hasId && hasType)
  {
    // Columns not in the table (row ids, block names...) keep their place in
    // front; the table's columns follow in its own order.
    std::stable_sort(order.begin(), order.end(), [&ranks](int a, int b) {
      return ranks[a] < ranks[b];
    });
  }
  QStringList shown;
  for (int visual = 0; visual < count; ++visual)
  {
    const int logical = order[visual];
    const int from = header->visualIndex(logical);
    if (from != visual && from >= 0)
    {
      header->moveSection(from, visual);
    }
    if (!header->isSectionHidden(logical))
    {
      shown << model->headerData(logical, Qt::Horizontal, Qt::DisplayRole).toString();
    }
  }
  if (vtkSMProxy* proxy = view->getProxy())
  {
    proxy->SetAnnotation("FEMorph.ColumnOrder", shown.join(',').toStdString().c_str());
  }
}
