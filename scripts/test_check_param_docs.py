#!/usr/bin/python3
"""Unit tests of scripts/check_param_docs.py: the parameter forms of our code are all found, and
an undocumented or stale parameter fails the check.

Usage: /usr/bin/python3 scripts/test_check_param_docs.py [--junit FILE]
"""

import os
import sys
import tempfile
import textwrap
import unittest

import check_param_docs as check
from junit import run_unit_tests

NODELET = textwrap.dedent("""\
    // A nodelet; "~commented" and pnh.param("in_comment", 1) are not reads.
    class Thing : public nodelet::Nodelet {
      void onInit() override {
        ros::NodeHandle& nh = getNodeHandle();
        ros::NodeHandle& pnh = getPrivateNodeHandle();
        rate_ = pnh.param("rate", 0.0);
        frame_ = pnh.param<std::string>("frame_id", "world");
        std::vector<std::string> pairs;
        if (!pnh.getParam("pairs", pairs)) {}
        pnh.param<std::map<std::string, int>>("nested", map_, {});
        nh.param("relative", relative_, 1);
        ros::param::get("/global", global_);
        id_ = deviceParam<std::string>(pnh, "camera_id", rig.camera_id, "");
        nh.param<std::string>(driver_ + "/pair_file", file_, "");
      }
    };
    PLUGINLIB_EXPORT_CLASS(demo::ThingNodelet, nodelet::Nodelet)
    """)

NODE = textwrap.dedent("""\
    int main(int argc, char** argv) {
      ros::init(argc, argv, "tool");
      ros::NodeHandle node_handle, private_handle("~");
      const int count = private_handle.param("count", 3);
    }
    """)

SCRIPT = textwrap.dedent("""\
    #!/usr/bin/env python3
    import rospy
    rospy.init_node("walker")
    scenes = rospy.get_param("~scenes", [])  # rospy.get_param("~commented")
    """)

PLUGINS = """<library path="lib/libdemo"><class name="demo/Thing" type="demo::ThingNodelet"
  base_class_type="nodelet::Nodelet"/></library>"""

README = textwrap.dedent("""\
    # demo

    ### `demo/Thing` nodelet

    #### Parameters

    | Name | Type | Default | Unit | Meaning |
    |---|---|---|---|---|
    | `~rate` | double | 0 | Hz | captures per second |
    | `~frame_id` | string | world | | frame |
    | `~pairs` | string list | | | pair ids |
    | `~nested` | map | | | a map |
    | `relative` | int | 1 | | relative name |
    | `/global` | int | | | global name |
    | `~camera_id` | string | | | vendor:product |
    | `<driver>/pair_file` | string | | | the driver's pair file |

    ### `tool`

    | Name | Type | Default | Unit | Meaning |
    |---|---|---|---|---|
    | `~count` | int | 3 | | how many |

    ### `walker` (scripts/walker)

    | Name | Type | Default | Unit | Meaning |
    |---|---|---|---|---|
    | `~scenes` | string list | [] | | scene files |
    """)


class PackageFixture(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.package = os.path.join(self.dir.name, "demo")
        self.write("package.xml", "<package><name>demo</name></package>")
        self.write("nodelet_plugins.xml", PLUGINS)
        self.write("src/nodelets/thing_nodelet.cpp", NODELET)
        self.write("src/nodes/tool.cpp", NODE)
        self.write("scripts/walker", SCRIPT)
        os.chmod(os.path.join(self.package, "scripts/walker"), 0o755)
        self.write("README.md", README)

    def tearDown(self):
        self.dir.cleanup()

    def write(self, relative, text):
        path = os.path.join(self.package, relative)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)

    def edit(self, relative, old, new):
        path = os.path.join(self.package, relative)
        text = open(path).read()
        self.assertIn(old, text)
        self.write(relative, text.replace(old, new))


class Extraction(PackageFixture):
    def test_every_form_of_our_code_is_found(self):
        nodes, problems = check.node_reads(self.package)
        self.assertEqual(problems, [])
        self.assertEqual(sorted(nodes["demo/Thing"]),
                         ["*/pair_file", "/global", "relative", "~camera_id", "~frame_id",
                          "~nested", "~pairs", "~rate"])
        self.assertEqual(sorted(nodes["tool"]), ["~count"])
        self.assertEqual(sorted(nodes["walker"]), ["~scenes"])

    def test_dynamic_reconfigure_parameters_belong_to_the_server(self):
        self.write("cfg/Settings.cfg", 'gen.add("exposure_ms", double_t, 0, "ms", 10.0)\n')
        self.edit("src/nodelets/thing_nodelet.cpp", "class Thing",
                  "dynamic_reconfigure::Server<demo::SettingsConfig> server_;\nclass Thing")
        nodes, _ = check.node_reads(self.package)
        self.assertIn("~exposure_ms", nodes["demo/Thing"])

    def test_diagnostic_updater_reads_its_period(self):
        self.edit("src/nodelets/thing_nodelet.cpp", "class Thing",
                  "std::unique_ptr<diagnostic_updater::Updater> diagnostics_;\nclass Thing")
        nodes, _ = check.node_reads(self.package)
        self.assertIn("~diagnostic_period", nodes["demo/Thing"])


class Check(PackageFixture):
    def test_documented_package_passes(self):
        problems, checked = check.check_package(self.package)
        self.assertEqual(problems, [])
        self.assertEqual(checked, 10)

    def test_undocumented_parameter_fails_naming_it(self):
        self.edit("src/nodes/tool.cpp", "param(\"count\", 3);",
                  "param(\"count\", 3);\n  const double gap = private_handle.param(\"gap\", 0.5);")
        problems, _ = check.check_package(self.package)
        self.assertEqual(len(problems), 1)
        self.assertIn("reads parameter ~gap of tool", problems[0])

    def test_documented_parameter_nobody_reads_fails(self):
        self.edit("README.md", "| `~count` |", "| `~stale` | int | 1 | | gone |\n| `~count` |")
        problems, _ = check.check_package(self.package)
        self.assertEqual(len(problems), 1)
        self.assertIn("documents parameter ~stale of tool", problems[0])

    def test_private_and_relative_names_differ(self):
        self.edit("README.md", "| `relative` |", "| `~relative` |")
        problems, _ = check.check_package(self.package)
        self.assertEqual(len(problems), 2)

    def test_node_without_section_fails(self):
        self.edit("README.md", "### `tool`", "### The tool")
        problems, _ = check.check_package(self.package)
        self.assertTrue(any("node tool reads ~count but has no" in p for p in problems), problems)


LAUNCH = """<launch>
  <node pkg="nodelet" type="nodelet" name="thing" args="load demo/Thing manager">
    <param name="rate" value="1.0"/>
    <rosparam param="pairs">[a, b]</rosparam>
    <param name="/global" value="1"/>
  </node>
  <group ns="x"><node pkg="demo" type="tool" name="tool"><param name="count" value="2"/></node></group>
  <node pkg="rviz" type="rviz" name="rviz"><param name="anything" value="1"/></node>
</launch>
"""


class LaunchFiles(PackageFixture):
    def problems(self):
        problems, _ = check.check_launch_files(self.dir.name, check.documented_rows)
        return problems

    def test_documented_parameters_pass(self):
        self.write("launch/demo.launch", LAUNCH)
        problems, checked = check.check_launch_files(self.dir.name, check.documented_rows)
        self.assertEqual(problems, [])
        self.assertEqual(checked, 3)  # rate, pairs, count; /global and rviz's are not ours

    def test_misspelt_parameter_fails(self):
        self.write("launch/demo.launch", LAUNCH.replace('"count"', '"cuont"'))
        problems = self.problems()
        self.assertEqual(len(problems), 1)
        self.assertIn("sets parameter ~cuont of node tool", problems[0])

    def test_launch_arg_without_doc_fails(self):
        self.write("launch/demo.launch", '<launch><arg name="rate" default="1" doc="Hz"/>'
                   '<arg name="gui" default="true"/><arg name="x" value="1"/></launch>')
        problems = self.problems()
        self.assertEqual(len(problems), 1)
        self.assertIn("arg gui has no doc", problems[0])

    def test_node_executable_that_loads_a_nodelet_is_the_nodelet(self):
        self.write("src/nodes/thing_node.cpp", 'int main() { loader.load(name, "demo/Thing", r, a); }')
        self.write("launch/demo.launch", '<launch><node pkg="demo" type="thing_node" name="t">'
                   '<param name="ratee" value="1"/></node></launch>')
        problems = self.problems()
        self.assertEqual(len(problems), 1)
        self.assertIn("~ratee of node t (demo/Thing)", problems[0])



if __name__ == "__main__":
    sys.exit(run_unit_tests(sys.modules[__name__], "check_param_docs_unit",
                            __doc__.split("\n\n")[0]))
