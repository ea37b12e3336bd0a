// The manifest of the malformed-input corpus: one line per case, written by
// generate_corpus next to the .vtu files it makes, read by run_corpus.
//
// Format: tab-separated, one case a line, lines starting with '#' are
// comments (the first names the columns). Columns, in order:
//   name        the case's name (unique; the .vtu is <name>.vtu)
//   file        the input .vtu, relative to the manifest's folder
//   reference   Improve's Reference input (.vtu, relative), or -
//   region      Improve's RegionArrayName, or -
//   damage      damage the .vtu format cannot hold, applied by the runner
//               after reading (';'-separated recipes, see below), or -
//   valid_on    filters that must accept the case and give a valid output
//               (no error allowed), ',' separated, "all", or -
//   report_on   filters that read the damaged array: each must report an
//               error or a warning containing every expected substring
//               (silently accepting the damage is a failure), or -
//   expect      the substrings those messages must contain, '|' separated,
//               or -
//   error_on    filters that must refuse the case with an error: the input
//               is corrupt (point ids out of range, a cell with the wrong
//               point count, NaN points...), so no output can be right, or -
//   filters     the filters the case is run through ("all" or a list)
//   timeout     seconds per (case, filter) before the child counts as hung
//   reader      "ok": the reader must read the file without an error;
//               "may-fail": the file is one the reader refuses (the filter
//               then gets the reader's empty output)
//   description free text
//
// Damage recipes (the XML reader refuses a cell or point array whose length
// differs from the cell or point count, so such arrays are made in memory):
//   truncate <cell|point|field> <name> <tuples>   keep the first tuples only
//                                                 (a new, smaller buffer)
//   extend <cell|point> <name> <tuples>           add tuples (copies of tuple 0)
//   drop-points                                   SetPoints(nullptr)
// A recipe starting with "ref:" applies to the Reference input.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace femorph_corpus
{

struct CaseEntry
{
  std::string Name;
  std::string File;
  std::string Reference = "-";
  std::string Region = "-";
  std::string Damage = "-";
  std::string ValidOn = "-";
  std::string ReportOn = "-";
  std::string Expect = "-";
  std::string ErrorOn = "-";
  std::string Filters = "all";
  int Timeout = 30;
  std::string Reader = "ok";
  std::string Description;
};

/// Splits `text` at `sep`; "-" and "" give an empty list.
inline std::vector<std::string> SplitList(const std::string& text, char sep)
{
  std::vector<std::string> parts;
  if (text.empty() || text == "-")
  {
    return parts;
  }
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, sep))
  {
    if (!part.empty())
    {
      parts.push_back(part);
    }
  }
  return parts;
}

/// True when the filter list `list` ("all", "-" or names) holds `filter`.
inline bool ListHas(const std::string& list, const std::string& filter)
{
  if (list == "all")
  {
    return true;
  }
  for (const std::string& name : SplitList(list, ','))
  {
    if (name == filter)
    {
      return true;
    }
  }
  return false;
}

inline void WriteManifestHeader(std::ostream& out)
{
  out << "#name\tfile\treference\tregion\tdamage\tvalid_on\treport_on\texpect\terror_on\tfilters"
         "\ttimeout\treader\tdescription\n";
}

inline void WriteManifestLine(std::ostream& out, const CaseEntry& c)
{
  out << c.Name << '\t' << c.File << '\t' << c.Reference << '\t' << c.Region << '\t' << c.Damage
      << '\t' << c.ValidOn << '\t' << c.ReportOn << '\t' << c.Expect << '\t' << c.ErrorOn << '\t'
      << c.Filters << '\t' << c.Timeout << '\t' << c.Reader << '\t' << c.Description << '\n';
}

/// Reads the manifest at `path`; false with `error` set when a line is malformed.
inline bool ReadManifest(const std::string& path, std::vector<CaseEntry>& cases, std::string& error)
{
  std::ifstream in(path);
  if (!in)
  {
    error = "cannot open " + path;
    return false;
  }
  std::string line;
  int number = 0;
  while (std::getline(in, line))
  {
    ++number;
    if (line.empty() || line[0] == '#')
    {
      continue;
    }
    std::vector<std::string> f;
    std::string field;
    std::istringstream fields(line);
    while (std::getline(fields, field, '\t'))
    {
      f.push_back(field);
    }
    if (f.size() != 13)
    {
      error = path + ":" + std::to_string(number) + ": " + std::to_string(f.size()) +
        " columns instead of 13";
      return false;
    }
    CaseEntry c;
    c.Name = f[0];
    c.File = f[1];
    c.Reference = f[2];
    c.Region = f[3];
    c.Damage = f[4];
    c.ValidOn = f[5];
    c.ReportOn = f[6];
    c.Expect = f[7];
    c.ErrorOn = f[8];
    c.Filters = f[9];
    c.Timeout = std::stoi(f[10]);
    c.Reader = f[11];
    c.Description = f[12];
    cases.push_back(c);
  }
  return true;
}

} // namespace femorph_corpus
