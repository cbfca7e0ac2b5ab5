"""Shared helpers of the pvpython tests: load the built plugin, fetch outputs, catch the
errors a filter reports (through VTK's ErrorEvent, so a test sees the exact message)."""
import os
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "Data")


def load_plugin(ns):
    """Loads the plugin given as the first argument (or HAIR_PLUGIN) into namespace ns."""
    path = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("HAIR_PLUGIN")
    if not path or not os.path.exists(path):
        sys.exit(f"give the path of the built HairDynamics.so (got {path!r})")
    LoadPlugin(path, remote=False, ns=ns)


class Errors:
    """Collects the error messages a proxy's VTK object reports."""

    def __init__(self, proxy):
        self.messages = []

        @calldata_type(VTK_STRING)
        def on_error(obj, event, message):
            self.messages.append(str(message))

        self._observer = on_error  # keep it alive as long as this object
        proxy.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)
        # The executive reports the failed request too; silence it, the filter's message is
        # the one a user needs.
        proxy.GetClientSideObject().GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)


def fetch(proxy, port=0):
    return servermanager.Fetch(proxy, None, None, port)


def table_columns(table):
    """A vtkTable's columns by name, as numpy arrays."""
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    return {table.GetColumnName(c): dsa.WrapDataObject(table).RowData[table.GetColumnName(c)]
            for c in range(table.GetNumberOfColumns())}


failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what)
    if not condition:
        failures.append(what)


def finish():
    print(f"{len(failures)} failed" if failures else "all checks passed")
    sys.exit(1 if failures else 0)
