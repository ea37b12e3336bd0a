"""FEMorph's VTK filters for Python: tetrahedral-mesh quality and editing.

Every class of the VTK module FEMorph::FEMorphFilters (vtkFEMorphMeshQuality,
vtkFEMorphSegment, vtkFEMorphImprove, vtkFEMorphHexToTet, vtkFEMorphTetToHex,
...) as a plain VTK algorithm, for pipelines in pvpython or in the Python
ParaView was built with (its vtkmodules package must be importable):

    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from femorph import vtkFEMorphSegment

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName("Data/boss_block.vtu")
    segment = vtkFEMorphSegment()
    segment.SetInputConnection(reader.GetOutputPort())
    segment.Update()

The classes' documentation is their C++ header's (help(vtkFEMorphSegment)).
"""
from .FEMorphFilters import *  # noqa: F401,F403  (the wrapped module's classes)
