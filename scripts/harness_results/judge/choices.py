"""Every analysis choice the judge makes, in one declarative table: its name, the value as written,
and each defensible alternative with one line of why. A specification (Spec) is one value per
choice; it is passed to every function that depends on it, never read from a module global.

The data-generating choices (the force, the voxel, the contact damping, the loading duration) are
the studies' axes: each claim declares which of them it compares over (judge/claims.py), and a
claim whose comparisons depend on one says where it holds and where it fails along it. The node
order is the ensemble's (harness run --ensemble), not a choice.
"""

import itertools


class Choice:
    """name: the key a Spec uses; value: as written; why: one line for it; alternatives: {value: why}."""

    def __init__(self, name, value, why, alternatives):
        self.name, self.value, self.why, self.alternatives = name, value, why, dict(alternatives)

    def values(self):
        return [self.value] + list(self.alternatives)


CHOICES = [
    Choice("chatter_length", "stated",
           "a run chatters when a node's motion about its window mean exceeds the length L its C++ class "
           "states (the largest of a grid detector's voxel, the reference's floor and a quarter of the mean "
           "spring length, core/run/window.hpp; rows made before the class: the error's motion against it)",
           {"half": "L halved: chatter of half a voxel is already visible in a figure",
            "double": "L doubled: the error's chatter is an upper bound on a node's motion about its mean",
            "edge": "a quarter of the mean spring length for every detector, not the voxel: a node moving "
                    "a few mm is visible to a user whatever the grid's resolution"}),
    Choice("contact_input_share", 0.02,
           "a run injects when the contact's net work per time scale over the window exceeds 2 % of the "
           "energy the bodies store (the C++ class's threshold, core/run/window.hpp)",
           {0.01: "1 %: half the gain already multiplies the stored energy 2.7 times over 100 crossings",
            0.05: "5 %: only a gain that would be seen within a few crossing times counts"}),
    Choice("floor", "reference",
           "an error's interval is its range over the final window widened by the floor of the reference "
           "it is measured against (reader.reference_floor: the last level's change, the larger of the last "
           "two where the loop is not in its asymptotic range)",
           {"double": "twice the floor: the floor is itself an estimate from two levels",
            "mesh": "the mesh floor beside it (the spheres' reference on a refined mesh, 1.1 mm): a "
                    "claim read as about the method rather than this mesh"}),
    Choice("tunnel_limit", 0,
           "a run that lets any node through the other body fails",
           {10: "up to 10 nodes through: a few surface nodes of a coarse mesh can slip between "
                "measured steps without the method failing"}),
    Choice("unstable_fails", True,
           "a run that is unstable (chatters, injects or grows) fails and loses to one that is not",
           {False: "an unstable run is compared by its window figures like a stable one: a user who "
                   "averages over the chatter sees them"}),
    Choice("auto_force", "apart",
           "the automatic force is reported apart from constant forces (the paper fixes the force "
           "by hand)",
           {"pooled": "the automatic force is one more force a user may choose"}),
    Choice("restriction_bound", "required",
           "(c): a restriction computes the bound of the shared region and moves points out of it (the "
           "paper: 'calculates the common penetration area bound and moves models points abroad this "
           "area'): the shared volume, or projection with its exact bound's time added",
           {"not required": "projection onto the exact surface moves points out of the other body "
                            "without computing a bound, and counts as a restriction"}),
    Choice("c_failures", "lose",
           "(c): a failing run loses: where every restriction fails and the penalty does not, the "
           "restriction is improper there (for the claim); where the penalty fails and a restriction does "
           "not, it is not (against); two failing runs are not compared",
           {"no cost": "a failing run's time is no cost: a place where either fails is listed, not compared"}),
    Choice("much", 2.0,
           "(c): a restriction costs much time when its collision unit takes at least twice the "
           "penalty's",
           {1.5: "half as much again is already a cost a real-time budget feels",
            5.0: "'much' read as an order of magnitude, rounded down"}),
    Choice("b_reading", "best",
           "(b): judged at the scene's best setting of the paper's model (its least error among the "
           "constant-force runs that do not fail), the one a practitioner would use",
           {"majority": "judged over every setting: more than half of the runs (failing ones included, "
                        "as not meeting it) meet (b)"}),
    Choice("p90_steps", 100,
           "(b): 'several iterations' is at most 100 steps (the 90th percentile of the episodes' lengths)",
           {30: "several read strictly: tens of steps",
            300: "several read loosely: the paper's own step is unknown"}),
    Choice("peak_share", 0.05,
           "(b): 'separate points' is at most 5 % of the guest's nodes penetrating at the peak",
           {0.01: "separate read strictly: one node in a hundred",
            0.10: "separate read loosely: one node in ten"}),
    Choice("open_share", 0.05,
           "(b): 'eliminated' is at most 5 % of the episodes left open at the end or gone through",
           {0.2: "eliminated read loosely: most episodes end outside"}),
    Choice("e_reading", "recall",
           "(e): 'collisions are detected' read end to end: the share of penetrating guest nodes the grid "
           "detects when it covers the host's whole box (a miss inside the region counts: the paper promises "
           "detection)",
           {"region": "only the misses the region causes: penetrating guest nodes outside the paper's "
                      "half-box region made large (its widest margin); the grid's inside test is not the "
                      "region's"}),
    Choice("e_miss", 0.0,
           "(e): 'collisions are detected' is every penetrating guest node detected (recall 1) when the "
           "grid covers the host's whole box",
           {0.05: "at most one penetrating node in twenty missed"}),
    Choice("exact_set", "inside tests",
           "(d): the exact detectors are the inside tests (hashing, CGAL); FCL tests triangle pairs and "
           "misses interior nodes (its recall is far below 1 on the bench)",
           {"with fcl": "FCL counts as an exact detector whatever its recall"}),
    Choice("rt_statistic", "median",
           "(rt): the collision unit's median time per step (the accuracy study's timing runs, the "
           "repeats' range as its interval) against the step's budget",
           {"p99": "its 99th-percentile step: real time every step, not on the typical one"}),
    Choice("rt_setting", "best",
           "(rt): the paper's model at its most accurate constant-force setting that does not fail",
           {"fastest helping": "its fastest setting that does not fail and ends closer to the reference than "
                               "no contact force (the row's helps): a real-time user trades accuracy for time"}),
]
BY_NAME = {c.name: c for c in CHOICES}


class Values:
    """One value per choice of `table` (the value as written where not given)."""

    table = ()

    def __init__(self, **values):
        names = {c.name for c in self.table}
        unknown = set(values) - names
        if unknown:
            raise KeyError("no such choice: %s" % ", ".join(sorted(unknown)))
        self.values = {c.name: values.get(c.name, c.value) for c in self.table}

    def __getattr__(self, name):
        try:
            return self.__dict__["values"][name]
        except KeyError:
            raise AttributeError(name)

    def changed(self):
        """[(name, value)] of the choices that differ from the value as written."""
        return [(c.name, self.values[c.name]) for c in self.table if self.values[c.name] != c.value]

    def name(self):
        ch = self.changed()
        return "as written" if not ch else ", ".join("%s=%s" % (k, v) for k, v in ch)


class Spec(Values):
    """A specification of the claims: one value per choice of CHOICES."""

    table = CHOICES


DEFAULT = Spec()


def all_specs():
    """Every combination of the choices' values (the first one: as written)."""
    names = [c.name for c in CHOICES]
    for combo in itertools.product(*(c.values() for c in CHOICES)):
        yield Spec(**dict(zip(names, combo)))


# The studies' own tables (the defaults of ablation.md, the accuracy front): not claims, so not in
# the specification curve; their thresholds are here beside the claims' so that every threshold of
# the package is in this module. Passed as a TableRules, never read from a global.
TABLE_CHOICES = [
    Choice("tie", 0.10,
           "(the front) two runs' errors differ only by more than 10 % of the larger (besides their chatters "
           "and the reference's floor)",
           {0.0: "no relative tie: the chatters and the floor alone are the noise",
            0.05: "a tighter tie: 5 %"}),
    Choice("tunnel_limit", 0,
           "(the front, the tables' useless mark) a run that lets any node through is not evidence",
           {10: "up to 10 nodes through: a coarse mesh's surface nodes may slip between measured steps"}),
    Choice("helps", 0.9,
           "(the defaults, the front) a setting helps when its position error, or its depth at no larger "
           "error, is at most 90 % of the run without contact force's",
           {0.5: "helping read strictly: half the no-force run's figure"}),
    Choice("within", 1.10,
           "(the defaults) settings within 10 % of the smallest error are tied and the smallest gap, then "
           "the fastest, decides among them",
           {1.0: "no tie: the smallest error alone"}),
]


class TableRules(Values):
    """The studies' tables' rules: one value per choice of TABLE_CHOICES."""

    table = TABLE_CHOICES


WRITTEN = TableRules()
