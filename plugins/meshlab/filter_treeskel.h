// MeshLab filter plugin: "Tree Skeleton (CPC)" and "Tree Mesh from Point Cloud" under Filters > Point Set.
// Compiled as C++14 against MeshLab 2020.09's headers; all the work is done by the treeskel library
// through bridge.h.
#pragma once

#include <common/interfaces.h>

class FilterTreeskelPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

public:
  enum { FP_TREE_SKELETON, FP_TREE_MESH };

  FilterTreeskelPlugin();

  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction* action) override;
  FILTER_ARITY filterArity(QAction* action) const override;
  int getPreConditions(QAction* action) const override;
  int getRequirements(QAction* action) override;
  int postCondition(QAction* action) const override;
  using MeshFilterInterface::initParameterSet;
  void initParameterSet(QAction* action, MeshModel& model, RichParameterList& parameters) override;
  bool applyFilter(QAction* action, MeshDocument& document, const RichParameterList& parameters,
                   vcg::CallBackPos* progress) override;

private:
  /// Reports `message` as the filter's error (and in the log) and returns false.
  bool fail(const QString& message);
};
