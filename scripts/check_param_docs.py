#!/usr/bin/python3
"""Check that every ROS parameter a node reads is documented in its package README, and that
every documented parameter is read.

Usage: /usr/bin/python3 scripts/check_param_docs.py [--junit FILE] [PACKAGE_DIR ...]

For each package (top-level folder with a package.xml; or the folders given), the parameters are
read off the code of its nodes, nodelets and plugins (src/, tools/, scripts/; not test/, bench/,
fuzz/):
  * C++: HANDLE.param("name", ...), HANDLE.param<T>("name", ...), HANDLE.getParam("name", ...),
    getParamCached, hasParam, searchParam, ros::param::get/param/has("name", ...), and helpers
    whose name contains "param" called as helper(HANDLE, "name", ...). A name read through a
    private handle (ros::NodeHandle pnh("~"), getPrivateNodeHandle(), a parameter named pnh or
    *private*) is "~name"; a computed name `expr + "/name"` is "*/name".
  * Python: rospy.get_param / has_param / search_param("name").
  * dynamic_reconfigure: gen.add("name", ...) of cfg/X.cfg, read by the file that serves
    dynamic_reconfigure::Server<XConfig>.
  * libraries: ~diagnostic_period, read by a diagnostic_updater::Updater (LIBRARY_READS).
Each file belongs to one node: a plugin's (PLUGINLIB_EXPORT_CLASS type looked up in the
package's plugin description XML files, e.g. body_scan_merge/Merge) or the executable named like
the file (src/nodes/save_cloud.cpp -> save_cloud).

In PACKAGE/README.md a node's section is a `###` heading naming it in backticks
(### `body_scan_merge/Merge` ...); its parameters are the rows of the tables under it whose
header has Default and Unit columns, first cell `~name` (or `name`, `<x>/name`).

It fails, naming the file, the node and the fix, when a parameter is read but not in its node's
table, a table row is read by no source of that node, a parameter-reading file belongs to no
node, or a node reading parameters has no section. It also checks the launch and rostest files
(launch/*.launch, test/*.test of every package): every private <param> or <rosparam param> a
file sets on one of our nodes (an executable, a nodelet loaded with `nodelet load`, or a
`*_node` that runs a nodelet) must be in that node's table, or in a table of the package's
non-nodelet plugins (the PairDriver's backends read its private parameters): a misspelt name
would be ignored silently. Every <arg> of a launch file (but value= ones) must have a doc=.
With --junit FILE it writes one JUnit test case per package (and one for the launch files) for
scripts/test_summary.py. Exit status 1 on any problem.
"""

import argparse
import glob
import os
import re
import sys
import time
import xml.etree.ElementTree as ET

from junit import write_junit

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE_DIRS = ("src", "tools", "scripts", "nodes")
SKIPPED_DIRS = {"test", "bench", "fuzz", "build"}

# "literal" or `expr + "/literal"` as the first argument.
NAME_ARG = r'(?P<expr>[\w.\->()]+\s*\+\s*)?"(?P<name>[^"]+)"'
TEMPLATE = r"(?:<(?:[^<>]|<[^<>]*>)*>)?"
HANDLE_CALL = re.compile(r"(?P<handle>\b\w+)\s*(?:\.|->)\s*(?:param|getParam|getParamCached|"
                         r"hasParam|searchParam)\s*" + TEMPLATE + r"\s*\(\s*" + NAME_ARG)
ROS_PARAM_CALL = re.compile(r"ros::param::(?:get|param|has|getCached|search)\s*" + TEMPLATE +
                            r"\s*\(\s*" + NAME_ARG)
HELPER_CALL = re.compile(r"\b\w*[Pp]aram\w*\s*" + TEMPLATE +
                         r"\s*\(\s*(?P<handle>\w+)\s*,\s*" + NAME_ARG)
PY_CALL = re.compile(r"rospy\.(?:get_param|has_param|search_param)\s*\(\s*"
                     r"[\"'](?P<name>[^\"']+)[\"']")
CFG_ADD = re.compile(r"\bgen\.add\s*\(\s*[\"'](?P<name>\w+)[\"']")
RECONFIGURE_SERVER = re.compile(r"dynamic_reconfigure::Server\s*<\s*(?:\w+::)*(\w+)Config\s*>")
PRIVATE_HANDLE_DECL = re.compile(
    r"ros::NodeHandle\s*&?\s*(\w+)\s*(?:\(\s*\"~\"\s*\)|=\s*(?:\w+\.)?getPrivateNodeHandle\(\)|"
    r"\{\s*\"~\"\s*\})|(\w+)\s*\(\s*\"~\"\s*\)")
# Parameters that a library class reads from the private handle it is given.
LIBRARY_READS = {"diagnostic_updater::Updater": ["~diagnostic_period"]}
PLUGIN_EXPORT = re.compile(r"PLUGINLIB_EXPORT_CLASS\s*\(\s*([\w:]+)\s*,")
PY_NODE = re.compile(r"rospy\.init_node\s*\(")
CPP_MAIN = re.compile(r"\bint\s+main\s*\(")


def strip_cpp_comments(text):
    """The code without // and /* */ comments (string literals kept)."""
    return re.sub(r'//[^\n]*|/\*.*?\*/|("(?:\\.|[^"\\])*")',
                  lambda m: m.group(1) or "", text, flags=re.S)


def strip_py_comments(text):
    return re.sub(r"#[^\n]*", "", text)


def is_private_handle(handle, private_handles):
    return handle in private_handles or handle == "pnh" or "private" in handle.lower()


def param_key(name, private, computed):
    """The parameter as documented: ~name (private), */name (computed prefix), name."""
    if computed:
        return "*/" + name.lstrip("/")
    if name.startswith("~"):
        return name
    return ("~" + name) if private else name


def cpp_reads(text):
    """{key: line} of the parameters a C++ file reads."""
    code = strip_cpp_comments(text)
    private_handles = {m.group(1) or m.group(2) for m in PRIVATE_HANDLE_DECL.finditer(code)}
    reads = {}

    def add(match, private):
        key = param_key(match.group("name"), private, bool(match.group("expr")))
        reads.setdefault(key, code.count("\n", 0, match.start()) + 1)

    for m in HANDLE_CALL.finditer(code):
        add(m, is_private_handle(m.group("handle"), private_handles))
    for m in ROS_PARAM_CALL.finditer(code):
        add(m, False)
    for m in HELPER_CALL.finditer(code):
        add(m, is_private_handle(m.group("handle"), private_handles))
    for library_class, keys in LIBRARY_READS.items():
        used = code.find(library_class)
        for key in keys if used >= 0 else []:
            reads.setdefault(key, code.count("\n", 0, used) + 1)
    return reads


def py_reads(text):
    code = strip_py_comments(text)
    return {m.group("name"): code.count("\n", 0, m.start()) + 1 for m in PY_CALL.finditer(code)}


def plugin_names(package_dir):
    """C++ type -> plugin name from the package's plugin description files."""
    names = {}
    for path in glob.glob(os.path.join(package_dir, "*.xml")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            continue
        for cls in root.iter("class"):
            if cls.get("type") and cls.get("name"):
                names[cls.get("type")] = cls.get("name")
    return names


def source_files(package_dir):
    for sub in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(package_dir, sub)):
            dirnames[:] = [d for d in dirnames if d not in SKIPPED_DIRS]
            for f in sorted(filenames):
                path = os.path.join(dirpath, f)
                if f.endswith((".cpp", ".h", ".hpp", ".py")):
                    yield path
                elif "." not in f and os.access(path, os.X_OK):
                    with open(path, errors="replace") as script:
                        if "python" in script.readline():
                            yield path


def node_reads(package_dir):
    """({node: {key: "file:line"}}, problems) of a package's code."""
    package_dir = os.path.abspath(package_dir)
    plugins = plugin_names(package_dir)
    cfg_params = {}
    for cfg in glob.glob(os.path.join(package_dir, "cfg", "*.cfg")):
        text = strip_py_comments(open(cfg).read())
        cfg_params[os.path.splitext(os.path.basename(cfg))[0]] = (
            os.path.relpath(cfg, ROOT), [m.group("name") for m in CFG_ADD.finditer(text)])
    nodes, problems = {}, []
    for path in source_files(package_dir):
        text = open(path, errors="replace").read()
        rel = os.path.relpath(path, ROOT)
        python = path.endswith(".py") or not os.path.splitext(path)[1]
        reads = py_reads(text) if python else cpp_reads(text)
        located = {key: "%s:%d" % (rel, line) for key, line in reads.items()}
        if not python:
            for config in RECONFIGURE_SERVER.findall(strip_cpp_comments(text)):
                if config in cfg_params:
                    cfg_rel, names = cfg_params[config]
                    for name in names:
                        located.setdefault("~" + name, cfg_rel)
        if not located:
            continue
        export = None if python else PLUGIN_EXPORT.search(text)
        if export:
            cpp_type = export.group(1).lstrip(":")
            node = plugins.get(cpp_type)
            if node is None:
                problems.append("%s: plugin %s reads parameters but is in no plugin description "
                                "XML of the package" % (rel, cpp_type))
                continue
        elif python or CPP_MAIN.search(text):
            node = os.path.splitext(os.path.basename(path))[0]
        else:
            problems.append("%s reads parameters (%s) but is neither a plugin nor a node's main "
                            "file: read them in the node and pass them on"
                            % (rel, ", ".join(sorted(located))))
            continue
        nodes.setdefault(node, {}).update(located)
    return nodes, problems


def readme_sections(readme):
    """[(heading, {documented key: line})] of the `###` sections of a README."""
    sections = []
    heading, table_header = None, None
    for number, line in enumerate(open(readme), 1):
        if line.startswith("### "):
            heading = line[4:].strip()
            sections.append((heading, {}))
            table_header = None
        elif line.startswith("#"):
            if line.startswith("## "):
                heading = None
            table_header = None
        elif line.lstrip().startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if table_header is None:
                table_header = [c.lower() for c in cells]
            elif (heading is not None and "default" in table_header and "unit" in table_header
                  and not set(cells[0]) <= set("-: ")):
                name = cells[0].strip("`").strip()
                sections[-1][1].setdefault(name, number)
        else:
            table_header = None
    return sections


def package_folders(root):
    """Package name -> folder, for every package.xml of the workspace."""
    folders = {}
    for path in glob.glob(os.path.join(root, "*", "package.xml")):
        name = ET.parse(path).getroot().findtext("name")
        folders[name.strip()] = os.path.dirname(path)
    return folders


def node_plugin(package_dir, executable):
    """The nodelet a `*_node` executable of the package loads (nodelet::Loader), else None."""
    for path in glob.glob(os.path.join(package_dir, "src", "**", executable + ".cpp"),
                          recursive=True):
        found = re.search(r'loader\.load\s*\([^;]*?"(\w+/\w+)"', open(path).read(), re.S)
        if found:
            return found.group(1)
    return None


def launch_nodes(element):
    """(node element, params it sets) of a launch tree, params as private keys ~name."""
    for node in element.iter("node"):
        params = []
        for child in node:
            name = child.get("name") if child.tag == "param" else (
                child.get("param") if child.tag == "rosparam" else None)
            if name and not name.startswith("/"):
                params.append(name if name.startswith("~") else "~" + name)
        yield node, params


def check_launch_files(root, documented_rows):
    """Problems of the launch and rostest files: parameters set on our nodes that their README
    does not document. documented_rows(package, node) gives the accepted rows or None."""
    folders = package_folders(root)
    problems, checked = [], 0
    files = sorted(glob.glob(os.path.join(root, "*", "launch", "*.launch")) +
                   glob.glob(os.path.join(root, "*", "test", "**", "*.test"), recursive=True))
    for path in files:
        rel = os.path.relpath(path, root)
        try:
            tree = ET.parse(path).getroot()
        except ET.ParseError as e:
            problems.append("%s: not XML (%s)" % (rel, e))
            continue
        if path.endswith(".launch"):
            for arg in tree.iter("arg"):
                if arg.get("value") is None and not (arg.get("doc") or "").strip():
                    problems.append("%s: arg %s has no doc=\"...\": say what it does"
                                    % (rel, arg.get("name")))
        for node, params in launch_nodes(tree):
            if not params:
                continue
            package, executable = node.get("pkg", ""), node.get("type", "")
            args = (node.get("args") or "").split()
            if package == "nodelet" and executable == "nodelet" and args[:1] == ["load"]:
                identity = args[1] if len(args) > 1 else ""
                package = identity.split("/")[0]
            elif package in folders:
                identity = node_plugin(folders[package], executable) or executable
            else:
                continue
            if package not in folders:
                continue
            rows = documented_rows(folders[package], identity)
            if rows is None:
                continue  # not a documented node (a test executable)
            for key in params:
                checked += 1
                if "$(" in key:
                    continue
                problem = ("%s sets parameter %s of node %s (%s), which %s/README.md does "
                           "not document: fix the name or document it"
                           % (rel, key, node.get("name"), identity,
                              os.path.basename(folders[package])))
                if not any(matches(row, key) for row in rows) and problem not in problems:
                    problems.append(problem)
    return problems, checked


def matches(documented, read_key):
    """Whether a documented row names a read: equal, or <x>/name for a computed */name."""
    if read_key.startswith("*/"):
        return documented.endswith(read_key[1:]) and documented != read_key[2:]
    return documented == read_key


def check_package(package_dir):
    """Problems of one package (list of strings) and the number of parameters checked."""
    name = os.path.basename(os.path.abspath(package_dir))
    nodes, problems = node_reads(package_dir)
    readme = os.path.join(package_dir, "README.md")
    if not nodes and not os.path.exists(readme):
        return problems, 0
    if not os.path.exists(readme):
        return problems + ["%s/README.md is missing: document the parameters of %s"
                           % (name, ", ".join(sorted(nodes)))], 0
    sections = readme_sections(readme)
    readme_rel = os.path.relpath(readme, ROOT)
    claimed = set()
    checked = 0
    for node, reads in sorted(nodes.items()):
        owners = [i for i, (heading, _) in enumerate(sections) if "`%s`" % node in heading]
        if not owners:
            problems.append("%s: node %s reads %s but has no `### ... \\`%s\\`` section with a "
                            "parameter table" % (readme_rel, node, ", ".join(sorted(reads)), node))
            continue
        documented = {}
        for i in owners:
            claimed.add(i)
            documented.update(sections[i][1])
        for key, where in sorted(reads.items()):
            checked += 1
            if not any(matches(row, key) for row in documented):
                problems.append("%s reads parameter %s of %s, which %s does not document: add a "
                                "row `%s` | type | default | unit | meaning to its Parameters "
                                "table" % (where, key, node, readme_rel, key))
        for row, line in sorted(documented.items()):
            if not any(matches(row, key) for key in reads):
                problems.append("%s:%d documents parameter %s of %s, which no source of %s reads:"
                                " remove the row or fix its name" % (readme_rel, line, row, node,
                                                                     node))
    for i, (heading, rows) in enumerate(sections):
        if rows and i not in claimed:
            problems.append("%s: section '%s' documents parameters (%s) but names no node that "
                            "reads parameters in backticks" % (readme_rel, heading,
                                                                ", ".join(sorted(rows))))
    return problems, checked


def documented_rows(package_dir, node):
    """The parameter rows a launch file may set on `node` of the package: its section's, and
    those of the package's plugins that are not nodelets (they read the node's private
    parameters); None when the README has no section for the node."""
    readme = os.path.join(package_dir, "README.md")
    if not os.path.exists(readme):
        return None
    sections = readme_sections(readme)
    own = [rows for heading, rows in sections if "`%s`" % node in heading]
    if not own:
        return None
    helpers = set()
    for path in glob.glob(os.path.join(package_dir, "*.xml")):
        try:
            for cls in ET.parse(path).getroot().iter("class"):
                if cls.get("base_class_type") != "nodelet::Nodelet" and cls.get("name"):
                    helpers.add(cls.get("name"))
        except ET.ParseError:
            continue
    rows = {}
    for heading, section_rows in sections:
        if any("`%s`" % name in heading for name in helpers | {node}):
            rows.update(section_rows)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("packages", nargs="*", help="package folders (default: all)")
    parser.add_argument("--junit", help="write a JUnit XML result file")
    args = parser.parse_args()
    packages = args.packages or sorted(
        os.path.dirname(p) for p in glob.glob(os.path.join(ROOT, "*", "package.xml")))
    cases, failed = [], False
    for package in packages:
        start = time.time()
        problems, checked = check_package(package)
        name = os.path.basename(os.path.abspath(package))
        for problem in problems:
            print(problem)
        failed |= bool(problems)
        cases.append((name, time.time() - start, "\n".join(problems) if problems else None,
                      "%d parameter reads documented" % checked))
        print("%s: %d parameter reads checked, %d problems" % (name, checked, len(problems)))
    if not args.packages:
        start = time.time()
        problems, checked = check_launch_files(ROOT, documented_rows)
        for problem in problems:
            print(problem)
        failed |= bool(problems)
        cases.append(("launch_files", time.time() - start,
                      "\n".join(problems) if problems else None,
                      "%d parameters set in launch files documented" % checked))
        print("launch and test files: %d parameters set checked, %d problems"
              % (checked, len(problems)))
    if args.junit:
        write_junit(args.junit, "param_docs", cases)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
