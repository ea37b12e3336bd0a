// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   pqFEMorphGUIStartup
 * @brief   FEMorph's GUI-only defaults, set when the ParaView client starts.
 *
 * Loaded only by the `paraview` GUI (pvpython, pvbatch and pvserver ignore a
 * plugin's UI interfaces):
 * - Segment's Regions table reads like a CAD feature list in the spreadsheet
 *   view: ParaView 5.11's vtkSpreadSheetView sorts a table's columns by name
 *   (vtkSpreadSheetView.cxx, OrderByNames, applied to every fetched block) and
 *   offers no order property, so this class moves the header sections of
 *   every spreadsheet that shows the RegionId and TypeName columns into the
 *   table's own order (vtkFEMorphSegmentationArrays::RegionTableColumns).
 *   Data, names and exports (CSV, Fetch) are unchanged.
 * - A colour map for arrays named RegionId that interprets values as
 *   categories, one distinct colour per region, through a settings collection
 *   below the site and user settings (a user's saved RegionId map wins).
 *
 * The visual column order it applied is kept in the view proxy's annotation
 * "FEMorph.ColumnOrder" (labels joined by ','), for scripts and tests.
 */
#ifndef pqFEMorphGUIStartup_h
#define pqFEMorphGUIStartup_h

#include <QObject>

class pqView;
class pqSpreadSheetView;

class pqFEMorphGUIStartup : public QObject
{
  Q_OBJECT
public:
  pqFEMorphGUIStartup(QObject* parent = nullptr);
  ~pqFEMorphGUIStartup() override = default;

  void onStartup();
  void onShutdown() {}

  /// Settings (JSON) that make RegionId's colour map categorical.
  static QString RegionIdColorSettings();

private Q_SLOTS:
  void onViewAdded(pqView* view);

private:
  void watch(pqSpreadSheetView* view);
  static void orderColumns(pqSpreadSheetView* view);
};

#endif
