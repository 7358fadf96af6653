# The public names of ``imagespace`` for type checkers, and the list the lazy loader reads at run time:
# ``lazy_loader.attach_stub`` in ``__init__.py`` turns every ``from . import m`` into a lazily
# imported submodule and every ``from .m import name`` into a lazily imported attribute, so this
# file is the one list of both (nothing is imported until it is used). The module aliases at the
# end (``isp.screws`` ...) are written as ``import``/assignment, which the loader skips: at run time
# they come from ``_MODULE_ALIASES`` in ``__init__.py`` (tests/test_typing.py holds the two equal).

from . import (
    core as core,
    solve as solve,
    singular as singular,
    paths as paths,
    design as design,
    atlas as atlas,
    spatial as spatial,
    dynamics as dynamics,
    examples as examples,
    manipulator as manipulator,
    plotting as plotting,
    widgets as widgets,
    drawing as drawing,
    cli as cli,
    tolerances as tolerances,
    exceptions as exceptions,
    display as display,
    spatial_surfaces as spatial_surfaces,
)

# the planar image space (core)
from .core.kinematic_map import (
    compose as compose,
    image_point as image_point,
    inverse as inverse,
    normalize as normalize,
    pose_of as pose_of,
    transform_matrix as transform_matrix,
    transform_points as transform_points,
)
from .core.quadrics import (
    Quadric as Quadric,
    image_symbols as image_symbols,
    pp_quadric as pp_quadric,
    pr_quadric as pr_quadric,
    rp_quadric as rp_quadric,
    rr_quadric as rr_quadric,
)
from .core.legs import (
    PPR as PPR,
    PRP as PRP,
    PRR as PRR,
    RPP as RPP,
    RPR as RPR,
    RRP as RRP,
    RRR as RRR,
    Leg as Leg,
)
from .core.mechanism import Mechanism as Mechanism
from .core.planar import PlanarMechanism as PlanarMechanism
from .core.certify import (
    RealRootCertificate as RealRootCertificate,
    certify_real_roots as certify_real_roots,
    certify_real_roots_batch as certify_real_roots_batch,
)

# errors, warnings, tolerances
from .exceptions import (
    AngleUnitWarning as AngleUnitWarning,
    DegenerateDesignError as DegenerateDesignError,
    EliminationError as EliminationError,
    ImageSpaceError as ImageSpaceError,
    InputError as InputError,
    InputTypeError as InputTypeError,
    RowIndexError as RowIndexError,
    NearSingularWarning as NearSingularWarning,
    RepeatedLegWarning as RepeatedLegWarning,
)
from .tolerances import TOLERANCES as TOLERANCES, Tolerances as Tolerances

# the planar manipulator and its direct kinematics
from .manipulator import (
    AssemblyMode as AssemblyMode,
    AssemblyModes as AssemblyModes,
    CertifiedModes as CertifiedModes,
    DKBatchResult as DKBatchResult,
    PlanarParallel as PlanarParallel,
)

# singularities
from .singular.surface import (
    ConicSection as ConicSection,
    SingularitySurface as SingularitySurface,
    singularity_surface as singularity_surface,
    singularity_surfaces as singularity_surfaces,
)
from .singular.jacobians import PoseJacobians as PoseJacobians, jacobians as jacobians
from .singular.meshing import (
    export_mesh as export_mesh,
    mesh_implicit as mesh_implicit,
    mesh_surface as mesh_surface,
)
from .singular.cusps import (
    cusp_edges as cusp_edges,
    cusps as cusps,
    linking_number as linking_number,
    mode_count_map as mode_count_map,
)

# paths
from .paths.check import (
    ImagePath as ImagePath,
    PathCheck as PathCheck,
    check_path as check_path,
    polyline as polyline,
    polynomial_curve as polynomial_curve,
    pose_segment as pose_segment,
    rational_curve as rational_curve,
    segment as segment,
    segments_free as segments_free,
)
from .paths.modechange import (
    ModeChangePlan as ModeChangePlan,
    joint_trajectory as joint_trajectory,
    plan_mode_change as plan_mode_change,
)
from .paths.cusp_loops import cusp_loop as cusp_loop
from .paths.backlash import backlash as backlash

# design
from .design.mobility import (
    gruebler as gruebler,
    manipulator_mobility as manipulator_mobility,
    mechanism_mobility as mechanism_mobility,
)
from .design.sweep import fuzzy_minmax as fuzzy_minmax, sweep as sweep

# the spatial platforms
from .spatial.gough_stewart import GoughStewart as GoughStewart
from .spatial.three_rps import ThreeRPS as ThreeRPS
from .spatial_surfaces import mesh_constant_orientation_singularity as mesh_constant_orientation_singularity

# the atlas of joint space
from .atlas import (
    CuspidalityResult as CuspidalityResult,
    JointAtlas as JointAtlas,
    atlas_figure as atlas_figure,
    is_cuspidal as is_cuspidal,
    joint_atlas as joint_atlas,
)

__version__: str

# module aliases: short names of modules in the layered packages (ARCHITECTURE.md), e.g. isp.screws
import imagespace.core.certify as _certify
import imagespace.core.codegen as _codegen
import imagespace.core.elimination as _elimination
import imagespace.core.kinematic_map as _kinematic_map
import imagespace.core.legs as _legs
import imagespace.core.quadrics as _constraints
import imagespace.core.roots as _roots
import imagespace.design.indices as _indices
import imagespace.design.mobility as _mobility
import imagespace.design.workspace as _workspace
import imagespace.paths.backlash as _clearance
import imagespace.paths.modechange as _modechange
import imagespace.singular.meshing as _meshing
import imagespace.singular.surface as _singularities
import imagespace.solve.certified as _certified_dk
import imagespace.solve.kernel as _fastdk
import imagespace.spatial.screws as _screws

kinematic_map = _kinematic_map
constraints = _constraints
legs = _legs
elimination = _elimination
roots = _roots
certify = _certify
codegen = _codegen
certified_dk = _certified_dk
fastdk = _fastdk
singularities = _singularities
meshing = _meshing
modechange = _modechange
clearance = _clearance
workspace = _workspace
indices = _indices
mobility = _mobility
screws = _screws
