"""Hair Simulation as ParaView loaded it: the Model enumeration and which properties each
model shows, evaluated from the property hints of the proxy (the XML generated from the model
registry, Plugin/GenerateSimulationXml.cxx). The expectations are written here by hand, from
what each model reads (docs/hair-simulation.md): a registry entry that shows a group to a model
that ignores it, or hides one it reads, fails.

usage: pvpython test_plugin_xml.py <plugin>
"""
from paraview import servermanager

from hairtest import check, finish, load_plugin

load_plugin(globals())
proxy = servermanager.ProxyManager().NewProxy("filters", "HairSimulation")
check(proxy is not None, "the HairSimulation proxy exists")

MODELS = {0: "Super-Helix", 1: "Projective", 2: "Discrete Elastic Rods"}
SUPER_HELIX_OPTIONS = {"Integrator", "Tolerance", "QuadratureTolerance"}
BODY_CONTACT_LAW = {"Contacts", "ContactStiffness", "ContactDamping", "ContactThickness",
                    "SlipVelocity"}
HAIR_GRID = {"HairHairContacts", "HairVolumeFraction", "HairVolume", "HairGridFriction",
             "HairGridCellSize"}
HAIR_PAIRS = {"HairContactThickness", "HairContactStiffness", "HairContactDamping",
              "HairFrictionCoefficient", "HairContactIterations", "HairContactPerLength"}
HIDDEN = {0: set(),
          1: SUPER_HELIX_OPTIONS | BODY_CONTACT_LAW | HAIR_GRID | HAIR_PAIRS,
          2: SUPER_HELIX_OPTIONS | HAIR_PAIRS}

# The enumeration, value by value.
domain = proxy.GetProperty("Model").GetDomain("enum")
entries = {domain.GetEntryValue(i): domain.GetEntryText(i)
           for i in range(domain.GetNumberOfEntries())}
check(entries == MODELS, f"the Model entries are {MODELS}: {entries}")


def shows(element, model):
    """Whether a decorator element shows its property for `model`; decorators on other
    properties than Model (the body motion's) are taken as showing it."""
    name = element.GetName()
    if name == "Expression":
        parts = [shows(element.GetNestedElement(i), model)
                 for i in range(element.GetNumberOfNestedElements())]
        return any(parts) if element.GetAttribute("type") == "or" else all(parts)
    kind = element.GetAttribute("type")
    if kind == "CompositeDecorator":
        return all(shows(element.GetNestedElement(i), model)
                   for i in range(element.GetNumberOfNestedElements()))
    if kind == "GenericDecorator" and element.GetAttribute("property") == "Model":
        match = int(element.GetAttribute("value")) == model
        return match != (element.GetAttribute("inverse") == "1")
    return True


names = []
iterator = proxy.NewPropertyIterator()
iterator.Begin()
while not iterator.IsAtEnd():
    names.append(iterator.GetKey())
    iterator.Next()
for model, label in MODELS.items():
    hidden = set()
    for name in names:
        hints = proxy.GetProperty(name).GetHints()
        if hints is None:
            continue
        for i in range(hints.GetNumberOfNestedElements()):
            element = hints.GetNestedElement(i)
            if element.GetName() == "PropertyWidgetDecorator" and not shows(element, model):
                hidden.add(name)
    check(hidden == HIDDEN[model],
          f"{label}: hidden {sorted(hidden)}, expected {sorted(HIDDEN[model])}")
    check(HIDDEN[model] <= set(names), f"{label}: the expected names are the proxy's properties")
finish()
