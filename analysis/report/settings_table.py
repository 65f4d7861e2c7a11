"""The settings table of the nearcap program (`nearcap settings`; docs/sweeps-and-report.md, "The settings
table") as the report scripts read it: the methods a sweep's or a bench's rows name, in the order the plots and
tables list them, with their descriptions, kinds and roles, and the colour each is drawn in.  The scripts spell no
method name: a method the table adds is listed in its place, and a part only one method plays (the timing
baseline, the corrected ZP+, ...) is found by its role.
"""
import json

VERSION = 1  # the nearcap-settings version read (kSettingsTableVersion in src/cli/cli_commands.hpp)
# The roles a table gives methods (src/cli/settings_command.cpp says what each means).
ROLES = ("timing-baseline", "zfail-baseline", "published-zpplus", "corrected-zpplus", "switch-policy")
# Each method's colour by name; a method of the table without one gets the next of SPARE_COLOURS, in the table's
# order, and a method the table does not hold grey.
PALETTE = {"zpass": "#d62728", "zfail": "#1f77b4", "zpplus": "#ff7f0e", "zpplus-corrected": "#2ca02c",
           "preload": "#9467bd", "doom3": "#8c564b", "doom3-bfg": "#e377c2", "ogre": "#bcbd22",
           "always-zfail": "#17becf", "atomiczp": "#aec7e8", "policy": "#000000"}
SPARE_COLOURS = ["#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5",
                 "#393b79", "#637939", "#8c6d31", "#843c39"]
UNKNOWN_COLOUR = "#7f7f7f"


class InputError(Exception):
    """An input file that cannot be read: `kind` is the nearcap error kind (io, parse, schema)."""

    def __init__(self, kind, message):
        super().__init__(message)
        self.kind = kind


class MethodTable:
    """The methods of a settings table (`nearcap settings`): their order, descriptions, kinds and roles, and the
    colour each is drawn in."""

    def __init__(self, table, source):
        def fail(kind, where, what):
            raise InputError(kind, f"{source}: {where}: {what}")

        if not isinstance(table, dict) or table.get("format") != "nearcap-settings":
            fail("parse", "format", "not a nearcap settings table (nearcap settings prints one)")
        version = table.get("version")
        if not isinstance(version, int) or isinstance(version, bool) or version != VERSION:
            fail("schema", "version", f"{json.dumps(version)} is not a version this report reads ({VERSION})")
        methods = table.get("methods")
        if not isinstance(methods, list):
            fail("schema", "methods", "expected an array")
        self.order, self.label, self.kind, self.holder = [], {}, {}, {}
        for k, entry in enumerate(methods):
            where = f"methods[{k}]"
            if not isinstance(entry, dict):
                fail("schema", where, "expected an object")
            for key in ("name", "label", "kind"):
                if not isinstance(entry.get(key), str) or (key == "name" and not entry[key]):
                    fail("schema", f"{where}.{key}", "expected a non-empty string" if key == "name" else
                         "expected a string")
            name = entry["name"]
            if name in self.label:
                fail("schema", f"{where}.name", f"'{name}' is named twice")
            roles = entry.get("roles", [])
            if not isinstance(roles, list) or not all(isinstance(r, str) for r in roles):
                fail("schema", f"{where}.roles", "expected an array of strings")
            for role in roles:
                if role in self.holder:
                    fail("schema", f"{where}.roles", f"role '{role}' is held by '{self.holder[role]}' already")
                self.holder[role] = name
            self.order.append(name)
            self.label[name], self.kind[name] = entry["label"], entry["kind"]
        choices = table.get("choices", [])
        if not isinstance(choices, list):
            fail("schema", "choices", "expected an array")
        self.choices = {}  # option -> (its help, {value: its help})
        for k, c in enumerate(choices):
            where = f"choices[{k}]"
            if not isinstance(c, dict) or not isinstance(c.get("option"), str) or \
                    not isinstance(c.get("help", ""), str) or not isinstance(c.get("values", []), list):
                fail("schema", where, "expected {\"option\": NAME, \"help\": TEXT, \"values\": [...]}")
            values = {}
            for j, v in enumerate(c.get("values", [])):
                if not isinstance(v, dict) or not isinstance(v.get("name"), str) or \
                        not isinstance(v.get("help", ""), str):
                    fail("schema", f"{where}.values[{j}]", "expected {\"name\": NAME, \"help\": TEXT}")
                values[v["name"]] = v.get("help", "")
            self.choices[c["option"]] = (c.get("help", ""), values)
        spare = iter(SPARE_COLOURS * (1 + len(self.order) // len(SPARE_COLOURS)))
        self.palette = {m: PALETTE[m] if m in PALETTE else next(spare) for m in self.order}

    def role(self, role):
        """The name of the method that has `role`; None when the table gives it to none."""
        return self.holder.get(role)

    def sorted(self, present):
        """The method names of the rows in the table's order; a variant ("zpplus [...]") after its method, and
        names the table does not hold last, by name."""
        order = {m: k for k, m in enumerate(self.order)}
        return sorted(present, key=lambda m: (order.get(base_method(m), len(order)), m))

    def variant_text(self, variant):
        """A variant's choices ("light-projection=rebased,l-near-scale=0.5") in words, from the table's
        choices: "light-projection=rebased (P_l formulation; origin at the near rectangle's centre),
        l-near-scale=0.5"; a choice the table does not describe stays as it is."""
        parts = []
        for choice in variant.split(","):
            option, _, value = choice.partition("=")
            lead, values = self.choices.get(option, ("", {}))
            said = "; ".join(t for t in (lead, values.get(value, "")) if t)
            parts.append(f"{choice} ({said})" if said else choice)
        return ", ".join(parts)

    def colour(self, method):
        if method in self.palette:
            return self.palette[method]
        # A variant: its method's hue, darker.
        base = self.palette.get(base_method(method), UNKNOWN_COLOUR)
        r, g, b = (int(base[k:k + 2], 16) for k in (1, 3, 5))
        return f"#{r * 3 // 5:02x}{g * 3 // 5:02x}{b * 3 // 5:02x}"


def base_method(method):
    """The method of a series: "zpplus" of "zpplus [light-projection=glfrustum]"."""
    return method.split(" [")[0]


def load_json(path, what):
    """The JSON value in the file `path`; InputError naming the file, and `what` it was to hold, otherwise.  A
    UTF-8 byte order mark at the start is skipped, as nearcap's JSON reader skips it."""
    try:
        with open(path, encoding="utf-8-sig") as handle:
            return json.load(handle)
    except OSError as e:
        raise InputError("io", f"{path}: cannot read the {what}: {e.strerror}")
    except ValueError as e:  # UnicodeDecodeError included
        raise InputError("parse", f"{path}: not JSON: {e}")


def read(settings):
    return MethodTable(load_json(settings, "settings table"), settings)
