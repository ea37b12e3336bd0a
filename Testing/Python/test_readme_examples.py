"""README.md's "Use from Python/VTK" and "Use from C++" lines are the ones that work.

  PYTHONPATH=build/lib/python3.11/dist-packages pvpython|python3 test_readme_examples.py \\
    --readme README.md --work DIR --python-destination lib/python3.11/dist-packages

  - the ```python blocks of "Use from Python/VTK" run, in this order, in DIR
    (with DIR/Data the repository's Data/, as the README's relative paths
    assume): the file they write holds the improved part with FaceRegion,
    and their numpy variables have the shapes the comments say;
  - that section's `export PYTHONPATH=...` lines end with the package folder
    the build uses (--python-destination);
  - every line of the ```cmake and ```cpp blocks of "Use from C++" is a line
    of Testing/External/CMakeLists.txt and femorph_external.cxx (the program
    the test Install.External builds against the installed tree and runs).
"""
import argparse
import os
import re
import sys

import numpy as np


def section(readme, title):
    """The text of the `## title` section."""
    match = re.search(r"^## %s\n(.*?)(?=^## |\Z)" % re.escape(title), readme, re.S | re.M)
    assert match, "README.md has no section '## %s'" % title
    return match.group(1)


def blocks(text, language):
    blocks = re.findall(r"^```%s\n(.*?)^```" % re.escape(language), text, re.S | re.M)
    assert blocks, "no ```%s block" % language
    return blocks


def check_python(text, work, data_dir, python_destination):
    for line in re.findall(r"^export PYTHONPATH=(\S+)$", text, re.M):
        assert line.endswith("/" + python_destination), \
            "README's PYTHONPATH %s does not end with %s" % (line, python_destination)
    os.makedirs(work, exist_ok=True)
    link = os.path.join(work, "Data")
    if not os.path.islink(link):
        os.symlink(data_dir, link)
    written = os.path.join(work, "boss_block_improved.vtu")
    if os.path.exists(written):
        os.remove(written)

    os.chdir(work)
    namespace = {"__name__": "readme"}
    for code in blocks(text, "python"):
        exec(compile(code, "README.md", "exec"), namespace)

    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    assert os.path.exists(written), "the README's pipeline wrote no %s" % written
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(written)
    reader.Update()
    out = reader.GetOutput()
    assert out.GetNumberOfCells() > 0, "empty output"
    assert out.GetCellData().GetArray("FaceRegion") is not None, "no FaceRegion in the output"
    face_region = np.asarray(namespace["face_region"])
    n_tets = namespace["segment"].GetOutput().GetNumberOfCells()
    assert face_region.shape == (n_tets, 4), face_region.shape
    assert len(namespace["vertex_class"]) == namespace["segment"].GetOutput().GetNumberOfPoints()
    n_regions = namespace["segment"].GetOutputDataObject(2).GetNumberOfRows()
    assert n_regions > 0 and len(namespace["areas"]) == n_regions
    assert face_region.max() == n_regions - 1
    print("Python blocks: %d tets -> %d, %d regions" % (n_tets, out.GetNumberOfCells(), n_regions))


def check_cxx(text, external):
    for language, name in (("cmake", "CMakeLists.txt"), ("cpp", "femorph_external.cxx")):
        with open(os.path.join(external, name)) as f:
            lines = {line.strip() for line in f}
        for block in blocks(text, language):
            for line in block.splitlines():
                if line.strip():
                    assert line.strip() in lines, \
                        "README's ```%s line is not in Testing/External/%s: %s" % (
                            language, name, line)
    print("C++ blocks: lines of Testing/External")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--readme", required=True)
    parser.add_argument("--work", required=True, help="folder the Python blocks run in")
    parser.add_argument("--python-destination", required=True,
                        help="the package folder below the build or install prefix")
    args = parser.parse_args()

    source = os.path.dirname(os.path.abspath(args.readme))
    with open(args.readme) as f:
        readme = f.read()
    check_cxx(section(readme, "Use from C++"), os.path.join(source, "Testing", "External"))
    check_python(section(readme, "Use from Python/VTK"), os.path.abspath(args.work),
                 os.path.join(source, "Data"), args.python_destination)
    print("OK: README's examples in %s" % sys.executable)


if __name__ == "__main__":
    main()
