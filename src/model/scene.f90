!> The scene as plain data: what the input file says, with defaults, before anything is built
!> (STYLE.md item 2). One type per namelist group of DESIGN.md §6; a scene holds one of each
!> single group and arrays of the repeatable ones. These types are also namelist objects
!> (src/io/input_reader.f90 reads `&rod_nml r%n_elements = 10 /`), so they hold no allocatable
!> components; variable-length inputs have a fixed capacity.
!>
!> Values that have no default and were not given keep the sentinels `unset_real`,
!> `unset_int`; strings that were not given are blank unless a default is stated.
module rs_model_scene
    use rs_core_kinds, only: rk
    use rs_model_section, only: shaped_section, section_values
    implicit none
    private

    public :: load_applies_to, sweep_value_count, sweep_values, sweep_member_count, &
        sweep_member_indices, step_count, record_time, body_inertia_tensor, inertia_tensor, rod_is_damped, &
        coordinate_axis, element_properties, rod_segment_count, axial_reference, &
        end_is_held

    !> Marks a real variable that was not given and has no default.
    real(rk), parameter, public :: unset_real = huge(1.0_rk)
    !> Marks an integer variable that was not given and has no default.
    integer, parameter, public :: unset_int = -huge(1)
    !> Capacity of time-function tables (&load and &actuator table_times, table_values).
    integer, parameter, public :: max_table = 512
    !> Capacity of generalized-Maxwell branches per rod (&rod maxwell_*).
    integer, parameter, public :: max_branches = 8
    !> Capacity of polyline centrelines (&rod points: 3 coordinates per point).
    integer, parameter, public :: max_polyline_points = 64
    !> Capacity of rest-curvature tables (&rod rest_curvature_table: 4 numbers per row).
    integer, parameter, public :: max_curvature_rows = 64
    !> Rods tied to one &plate.
    integer, parameter, public :: max_plate_rods = 128
    !> Capacity of the values of one &sweep (values = ...; also the largest count of linspace
    !> and logspace).
    integer, parameter, public :: max_sweep_values = 4096
    !> Largest number of members of a scene's sweeps (the product of their value counts).
    integer, parameter, public :: max_sweep_members = 1000000
    !> Length of name-like strings (rod names, formulation names, kinds).
    integer, parameter, public :: name_len = 64
    !> Length of free text (titles, paths, option strings).
    integer, parameter, public :: text_len = 512

    !> The &rod variables that a section with its material determines (DESIGN.md §1).
    character(len=*), parameter, public :: section_derived_names(9) = [character(len=5) :: &
        'EA', 'GA1', 'GA2', 'EI1', 'EI2', 'GJ', 'rhoA', 'rhoI1', 'rhoI2']

    !> &run: what the run is and its global choices.
    type, public :: run_input_t
        character(len=text_len) :: title = ''
        !> Blank until resolved: then the default formulation of the registry
        !> (rs_formulations_registry, filled by rs_io_input_check).
        character(len=name_len) :: formulation_default = ''
        character(len=name_len) :: log_level = 'info'
        !> System of units the scene's numbers are in (rs_model_units); the solver is
        !> unit-agnostic, only the unit names shown change.
        character(len=name_len) :: units = 'si'
        !> Seconds between two progress lines of a long run.
        real(rk) :: progress_interval = 5.0_rk
        !> A result file whose checkpoint the run continues from ('' = start at t = 0).
        character(len=text_len) :: restart_from = ''
    end type run_input_t

    !> &time: the time interval and the time-stepping scheme.
    type, public :: time_input_t
        real(rk) :: t_end = unset_real
        real(rk) :: dt = unset_real
        !> 'midpoint' or 'generalized_alpha' (se3_pg; issue 25 item 3) with its rho_inf.
        character(len=name_len) :: scheme = 'midpoint'
        real(rk) :: rho_inf = 0.9_rk
        !> Order of the time integrator (issue 25 item 1): 2, the midpoint step; 4, Suzuki's
        !> composition of five midpoint steps (docs/theory/time_integration.md).
        integer :: order = 2
        !> Error-controlled steps (issue 25 item 2): dt is then the record interval, the steps
        !> inside it are chosen from the local error, weighed by rtol and atol, between dt_min
        !> and dt_max, starting from dt_initial (defaults: dt_max = dt, dt_initial = dt / 100,
        !> dt_min = 1e-12 t_end, set by the input's defaults pass).
        logical :: adaptive = .false.
        real(rk) :: rtol = 1.0e-6_rk
        real(rk) :: atol = 1.0e-9_rk
        real(rk) :: dt_min = unset_real
        real(rk) :: dt_max = unset_real
        real(rk) :: dt_initial = unset_real
        logical :: quasistatic = .false.
        !> Quasistatics: the equilibrium solves at t = 0 and t_end around the midpoint load steps
        !> (DESIGN.md §3); .false. leaves the midpoint load path alone (seed 001's pseudo-time
        !> stepping, whose last record depends on dt: methods/ph_planar.md §6.2, Fig. 7 right).
        logical :: equilibrium_solves = .true.
        !> Statics by damped dynamics (seed 004, methods/se3_strands.md §3.7): the run stops as
        !> soon as the kinetic energy of every system is below kinetic_energy_tol (t_end is then
        !> the latest time).
        logical :: relaxation = .false.
        real(rk) :: kinetic_energy_tol = 1.0e-12_rk
        !> A dynamic run that starts in static equilibrium (issue 26 item 3): first the static
        !> problem with the loads and supports at t = 0, continued from the initial placement
        !> (DESIGN.md §3, "Quasistatics"), then the dynamics from that state at rest
        !> (docs/theory/prestretched_starts.md).
        logical :: initial_equilibrium = .false.
        !> Quasistatics along the equilibrium path by arc-length continuation (issue 27 item 3,
        !> docs/theory/continuation.md): 'arc_length', the load time an unknown of at most
        !> path_steps steps of first length arc_length (at most arc_length_max) that end when
        !> it passes t_end; 'none', load steps of dt.
        character(len=name_len) :: continuation = 'none'
        real(rk) :: arc_length = 0.05_rk
        real(rk) :: arc_length_max = 0.2_rk
        integer :: path_steps = 200
        !> Leave the path at the first bifurcation it crosses for the branch that bifurcates
        !> there (docs/theory/continuation.md, "Bifurcations").
        logical :: branch_switch = .false.
        !> Line of the &time group (set by the reader; not an input variable).
        integer :: input_line = 0
    end type time_input_t

    !> &solver: Newton's stopping rule, cut-backs and PETSc options (DESIGN.md §3).
    type, public :: solver_input_t
        real(rk) :: newton_atol = 1.0e-10_rk
        real(rk) :: newton_rtol = 0.0_rk
        integer :: max_newton = 25
        integer :: max_cutbacks = 6
        logical :: condense_stresses = .false.
        real(rk) :: jacobian_reuse = 0.0_rk
        character(len=text_len) :: petsc_options = ''
    end type solver_input_t

    !> &output: where results go and how often (DESIGN.md §7).
    type, public :: output_input_t
        character(len=text_len) :: path = ''
        integer :: stride = 1
        character(len=text_len) :: fields = 'all'
        integer :: flush_every = 10
        logical :: xdmf = .true.
    end type output_input_t

    !> &rod: geometry, section, material and discretization of one rod.
    type, public :: rod_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: name = ''
        character(len=name_len) :: formulation = ''
        integer :: n_elements = unset_int
        integer :: degree = 2
        !> Resolved by the input check: 1 for cl_em_planar (reduced, free of shear locking), else 2.
        integer :: n_gauss = unset_int
        !> Formulation as resolved from: 'rod' (given in &rod), 'default' (&run
        !> formulation_default) or 'auto' (set by the resolver; not an input variable).
        character(len=name_len) :: formulation_origin = ''
        !> Why 'auto' chose the formulation it did (set by the resolver, e.g. "the rods, loads
        !> and velocities lie in the plane ..." or "3D because ..."; not an input variable).
        character(len=text_len) :: formulation_reason = ''
        !> cl_em_planar only (methods/ph_planar.md §5): 'stander_stein' (the classical
        !> energy-momentum scheme, §5.1) or 'ph_irreducible' (the displacement-based PH-EM
        !> scheme, §5.2). Blank = not given; the resolver sets 'stander_stein' for cl_em_planar
        !> rods and refuses a given value for any other formulation.
        character(len=name_len) :: em_variant = ''
        !> Reference centreline (rs_model_rod_geometry): 'straight', 'helix', 'polyline' or
        !> 'curvature'.
        character(len=name_len) :: geometry = 'straight'
        !> Start, direction (helix: axis) and rotation_center default to (0, 0, 0), e_x and
        !> start; they are unset until resolved so that a value given for a polyline, where
        !> they are derived, can be checked against the points.
        real(rk) :: start(3) = unset_real
        real(rk) :: direction(3) = unset_real
        real(rk) :: d1(3) = unset_real
        real(rk) :: length = unset_real
        real(rk) :: helix_radius = unset_real
        real(rk) :: helix_pitch = unset_real
        real(rk) :: helix_turns = unset_real
        !> Polyline vertices x1, y1, z1, x2, ... (the leading given entries).
        real(rk) :: points(3 * max_polyline_points) = unset_real
        !> Curvature only (rs_model_rest_curvature): the constant Darboux vector (kappa1, kappa2,
        !> kappa3) in material components, or the rows s, kappa1, kappa2, kappa3 of a table
        !> (the leading given entries), piecewise linear in s.
        real(rk) :: rest_curvature(3) = unset_real
        real(rk) :: rest_curvature_table(4 * max_curvature_rows) = unset_real
        !> Initial rigid-body velocity field: v(s) = velocity + angular_velocity x
        !> (phi(s) - rotation_center), director rates angular_velocity x d_i.
        real(rk) :: velocity(3) = 0.0_rk
        real(rk) :: angular_velocity(3) = 0.0_rk
        real(rk) :: rotation_center(3) = unset_real
        character(len=name_len) :: section = 'none'
        real(rk) :: radius = unset_real
        real(rk) :: inner_radius = unset_real
        real(rk) :: width = unset_real
        real(rk) :: height = unset_real
        real(rk) :: E = unset_real
        real(rk) :: G = unset_real
        real(rk) :: nu = unset_real
        real(rk) :: density = unset_real
        real(rk) :: EA = unset_real
        real(rk) :: GA1 = unset_real
        real(rk) :: GA2 = unset_real
        real(rk) :: EI1 = unset_real
        real(rk) :: EI2 = unset_real
        real(rk) :: GJ = unset_real
        real(rk) :: rhoA = unset_real
        real(rk) :: rhoI1 = unset_real
        real(rk) :: rhoI2 = unset_real
        real(rk) :: shear_factor = unset_real
        character(len=name_len) :: torsion_constant = ''
        logical :: prestressed = .false.
        !> Axial prestrain (issue 26 item 3): the given geometry is the rod stretched by this
        !> strain from its stress-free state, which is the geometry shortened along its arc
        !> length by 1 / (1 + prestrain) with the same shape; stiffnesses, inertias and masses
        !> are those of the stress-free rod (element_properties, axial_reference;
        !> docs/theory/prestretched_starts.md).
        real(rk) :: prestrain = 0.0_rk
        character(len=name_len) :: constraint = 'none'
        !> Stiffnesses made infinite besides those of `constraint` (issue 26 item 2): any of
        !> 'EA', 'GA1', 'GA2', 'EI1', 'EI2', 'GJ' (leading given entries; '' unset).
        character(len=8) :: rigid(6) = ''
        !> Generalized Maxwell branches (seed 000 §5.1, methods §3.1): branch i takes the
        !> fraction maxwell_fraction(i) of every stiffness, relaxes with tau_E (dilatation,
        !> bending) and tau_G (shear, torsion); the elastic branch keeps 1 - sum of fractions.
        !> The leading set entries define the branches.
        real(rk) :: maxwell_fraction(max_branches) = unset_real
        real(rk) :: maxwell_tau_E(max_branches) = unset_real
        real(rk) :: maxwell_tau_G(max_branches) = unset_real
        !> se3_strand only (seed 004 eq. 7, methods/se3_strands.md §2.5-2.6): the external drag
        !> D_ex = external_damping I6 (body force -D_ex V) and the internal dissipation
        !> D_in = internal_damping I6 (body force -D_in dU/dt, not sign-definite).
        real(rk) :: external_damping = 0.0_rk
        real(rk) :: internal_damping = 0.0_rk
        !> Damping of every formulation that has it (capability_t damping; issue 26 item 1):
        !> the Kelvin-Voigt viscous stress tau_i k_i d(strain_i)/dt added to each elastic stress
        !> component i, with the time constants in the order of the stiffnesses
        !> (EA, GA1, GA2, EI1, EI2, GJ) (one value given: all six; resolved to 0 when none is);
        !> and the external drag, the force -drag v per length against the centreline velocity
        !> v and the moment -angular_drag w per length against the angular velocity w.
        real(rk) :: kelvin_voigt_time(6) = unset_real
        real(rk) :: drag = 0.0_rk
        real(rk) :: angular_drag = 0.0_rk
        !> se3_strand only: the free end's half cell (docs/theory/se3_strand.md, "The free
        !> end"): 'balanced' (its segment's ad^T term in full: no spurious end moment) or
        !> 'paper' (seed 004's average with the ghost segment, for its h^2 tip table);
        !> resolved to 'balanced' for se3_strand rods.
        character(len=name_len) :: free_end = ''
        !> Radius of the rod's surface in rod-rod contact (&contact); default: the circle
        !> section's radius.
        real(rk) :: contact_radius = unset_real
        !> Helix only: angle (rad) of the start point about the axis, measured from the
        !> default normal of the axis (rs_model_rod_geometry): lays wires of a strand around
        !> one axis.
        real(rk) :: helix_phase = 0.0_rk
    end type rod_input_t

    !> &segment: a part of a rod with its own section, material, stiffnesses and inertias
    !> (issue 26 item 5). It runs from the previous segment's s_end of the same rod (0 for the
    !> first) to its own s_end; the part after the last segment keeps the rod's values. Every
    !> variable not given is the rod's (resolved: its unresolved section and material with
    !> the segment's given ones, then the segment's given stiffnesses and inertias on top),
    !> which the resolver stores in `values`. Each s_end is a node of the rod's uniform mesh,
    !> so every element lies in one segment.
    type, public :: segment_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: rod = ''
        real(rk) :: s_end = unset_real
        character(len=name_len) :: section = ''
        real(rk) :: radius = unset_real
        real(rk) :: inner_radius = unset_real
        real(rk) :: width = unset_real
        real(rk) :: height = unset_real
        real(rk) :: E = unset_real
        real(rk) :: G = unset_real
        real(rk) :: nu = unset_real
        real(rk) :: density = unset_real
        real(rk) :: EA = unset_real
        real(rk) :: GA1 = unset_real
        real(rk) :: GA2 = unset_real
        real(rk) :: EI1 = unset_real
        real(rk) :: EI2 = unset_real
        real(rk) :: GJ = unset_real
        real(rk) :: rhoA = unset_real
        real(rk) :: rhoI1 = unset_real
        real(rk) :: rhoI2 = unset_real
        real(rk) :: shear_factor = unset_real
        character(len=name_len) :: torsion_constant = ''
        !> A linear taper (issue 26 item 5): the section's dimensions at s_end; at the
        !> segment's start they are its radius, inner_radius, width and height.
        real(rk) :: radius_end = unset_real
        real(rk) :: inner_radius_end = unset_real
        real(rk) :: width_end = unset_real
        real(rk) :: height_end = unset_real
        !> The resolved EA, GA1, GA2, EI1, EI2, GJ, rhoA, rhoI1, rhoI2 of the segment (in the
        !> order of section_derived_names; set by the resolver, not input variables); of its
        !> start if it tapers.
        real(rk) :: values(9) = unset_real
        !> Resolved, not input variables: where the segment starts; a taper's shape ('' if
        !> the segment does not taper), its dimensions (radius, inner_radius, width, height)
        !> at the start (1) and the end (2), its material (E, G, density, shear_factor) and
        !> torsion constant (Saint-Venant's if saint_venant, else polar).
        real(rk) :: s_start = 0.0_rk
        character(len=name_len) :: taper = ''
        real(rk) :: taper_dims(4, 2) = 0.0_rk
        real(rk) :: taper_material(4) = 0.0_rk
        logical :: saint_venant = .false.
    end type segment_input_t

    !> &bc: the support at one end of a rod.
    type, public :: bc_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: rod = ''
        character(len=name_len) :: end = ''
        character(len=name_len) :: kind = ''
        !> A driven end (kind = 'driven') of a formulation that drives ends by their pose
        !> (capability_t drive = 'pose'): the end's reference pose moved by the displacement
        !> f(t) displacement and turned by the rotation vector f(t) rotation (inertial
        !> components, about the end's reference position), f the time function.
        real(rk) :: displacement(3) = 0.0_rk
        real(rk) :: rotation(3) = 0.0_rk
        !> A driven end of a formulation that drives ends by their velocity (drive =
        !> 'velocity'): the end section moves with velocity f(t) velocity and turns with angular
        !> velocity f(t) angular_velocity (inertial components, about the end's own position).
        !> Several such &bc on one end add up.
        real(rk) :: velocity(3) = 0.0_rk
        real(rk) :: angular_velocity(3) = 0.0_rk
        !> A sliding end (kind = 'sliding', a prismatic support; issue 26 item 3): the direction
        !> (inertial components) along which the end's position is free; across it the position
        !> is held, and the end's rotation is held.
        real(rk) :: axis(3) = unset_real
        !> A clamped or pinned end held until this time and free afterwards (issue 26 item 3;
        !> unset: held throughout): a rope released from a pin (docs/theory/
        !> prestretched_starts.md, "Release").
        real(rk) :: release_time = unset_real
        !> An end held in chosen directions (kind = 'held'; issue 26 item 3): which of the
        !> position's inertial coordinates 'x', 'y', 'z' and whether its 'rotation' are held
        !> (rs_model_support resolves every kind of support to such a hold).
        character(len=name_len) :: hold(4) = ''
        character(len=name_len) :: time_function = 'constant'
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = unset_real
        real(rk) :: table_times(max_table) = unset_real
        real(rk) :: table_values(max_table) = unset_real
        !> A rigid body on the end (kind = 'body'; issue 24 item 4): its mass, its centre of mass
        !> relative to the end's node and its inertia tensor about the centre of mass
        !> (diagonal and products, inertial components in the reference configuration).
        real(rk) :: mass = unset_real
        real(rk) :: centre(3) = 0.0_rk
        real(rk) :: inertia(3) = 0.0_rk
        real(rk) :: inertia_products(3) = 0.0_rk
    end type bc_input_t

    !> &load: an end load, a distributed load or gravity, scaled by a time function.
    type, public :: load_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: rod = ''
        character(len=name_len) :: where = ''
        real(rk) :: force(3) = 0.0_rk
        real(rk) :: moment(3) = 0.0_rk
        real(rk) :: acceleration(3) = 0.0_rk
        character(len=name_len) :: frame = 'spatial'
        character(len=name_len) :: time_function = 'constant'
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = unset_real
        real(rk) :: table_times(max_table) = unset_real
        real(rk) :: table_values(max_table) = unset_real
    end type load_input_t

    !> &actuator: a pneumatic chamber or a tendon along a whole rod (seed 000 §5.2, methods
    !> §3.2), at material offset (rho^1, rho^2) in the (d1, d2) basis. Its force
    !> tau(t) = -pressure area f(t) (pneumatic: a pressurized chamber pushes its end caps
    !> apart) or tension f(t) (tendon), with f the time function.
    type, public :: actuator_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: rod = ''
        character(len=name_len) :: kind = ''
        real(rk) :: offset(2) = unset_real
        real(rk) :: area = unset_real
        real(rk) :: pressure = unset_real
        real(rk) :: tension = unset_real
        character(len=name_len) :: time_function = 'constant'
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = unset_real
        real(rk) :: table_times(max_table) = unset_real
        real(rk) :: table_values(max_table) = unset_real
    end type actuator_input_t

    !> &joint: two rod ends tied together (DESIGN.md §5: shared nodal unknowns). 'revolute':
    !> shared position, independent rotations (a pin between the rods); 'rigid': shared position
    !> and rotation; 'spherical': shared position (3D).
    type, public :: joint_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: rod_a = ''
        character(len=name_len) :: end_a = ''
        character(len=name_len) :: rod_b = ''
        character(len=name_len) :: end_b = ''
        character(len=name_len) :: kind = ''
        !> 'revolute' in 3D: the hinge axis in the reference configuration (inertial
        !> components, normalized); it stays fixed in both end sections. Planar formulations
        !> turn about e_z and leave it unset.
        real(rk) :: axis(3) = unset_real
    end type joint_input_t

    !> &plate: a rigid end plate to which rod ends are tied (issue 10: bundles clamped to
    !> common end plates). Each listed end keeps its reference position and orientation
    !> relative to the plate; the plate is fixed, or driven: moved by f(t) displacement and
    !> turned by the rotation vector f(t) rotation about `centre` (inertial components; f the
    !> time function). A pull is a displacement along the bundle, a twist a rotation about it.
    !> A plate with a mass floats (issue 24 item 4): a rigid body moved by the rods tied to it.
    type, public :: plate_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: name = ''
        !> The rods tied to the plate (leading given entries) and their tied end ('start' or
        !> 'end', the same for all).
        character(len=name_len) :: rods(max_plate_rods) = ''
        character(len=name_len) :: end = ''
        !> Centre of the plate's rotation; default: the mean reference position of its ends.
        real(rk) :: centre(3) = unset_real
        real(rk) :: displacement(3) = 0.0_rk
        real(rk) :: rotation(3) = 0.0_rk
        character(len=name_len) :: time_function = 'constant'
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = unset_real
        real(rk) :: table_times(max_table) = unset_real
        real(rk) :: table_values(max_table) = unset_real
        !> A floating plate: its mass (0: fixed or driven), its centre of mass `centre` and its
        !> inertia tensor about it (diagonal and products, inertial components in the
        !> reference configuration), as a body on an end (bc_input_t).
        real(rk) :: mass = 0.0_rk
        real(rk) :: inertia(3) = 0.0_rk
        real(rk) :: inertia_products(3) = 0.0_rk
    end type plate_input_t

    !> &contact: rod-rod and self contact between all rods of the scene (issue 10, DESIGN.md
    !> §5): the penalty potential of rs_contact_potential between Gauss points of elements
    !> closer than the contact distance radius_a + radius_b (each rod's contact_radius).
    type, public :: contact_input_t
        !> The group was given (set by the reader; not an input variable): contact is on.
        logical :: given = .false.
        integer :: input_line = 0
        !> Penalty stiffness k (N/m^3: the pair potential is an energy per length squared).
        real(rk) :: stiffness = unset_real
        !> Broad-phase margin (m) added to the contact distance when candidate pairs are
        !> collected; default: the largest contact_radius.
        real(rk) :: margin = unset_real
        !> Elements of one rod this many or fewer apart along it are never a pair (self
        !> contact); default: derived from the contact distance and the element length.
        integer :: skip = unset_int
        !> Self contact of a rod beyond `skip` elements.
        logical :: self_contact = .true.
        !> Coulomb friction coefficient (0: frictionless) and the slip velocity (m/s) below which
        !> the regularized law is viscous (rs_contact_potential, Friction).
        real(rk) :: mu = 0.0_rk
        real(rk) :: slip_velocity = 1.0e-4_rk
        !> Contact points (Gauss points) per element; default: enough to resolve the contact
        !> patch at a penetration of 5% of the contact distance (docs/theory/bundles.md).
        integer :: points_per_element = unset_int
    end type contact_input_t

    !> &obstacle: a rigid obstacle, fixed or translated by a time function, that every rod of
    !> the scene touches with its contact_radius (issue 24 item 3): the ground ('plane': the
    !> half-space below the plane through `point` with outward `normal`), a 'sphere' (centre
    !> `point`, `radius`) or an infinite 'cylinder' (axis through `point` along `normal`,
    !> `radius`), with the penalty potential, its discrete gradient and regularized Coulomb
    !> friction of rs_contact_obstacle (energy exact without friction).
    type, public :: obstacle_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        character(len=name_len) :: name = ''
        character(len=name_len) :: kind = ''
        real(rk) :: point(3) = 0.0_rk
        !> 'plane': the outward normal; 'cylinder': the axis (normalized by the checks).
        real(rk) :: normal(3) = unset_real
        real(rk) :: radius = unset_real
        !> Penalty stiffness k (N/m^3): a point penetrating by delta carries k delta^2 per length.
        real(rk) :: stiffness = unset_real
        !> Coulomb friction coefficient (0: frictionless) and the slip velocity (m/s) below which
        !> the regularized law is viscous (rs_contact_obstacle).
        real(rk) :: mu = 0.0_rk
        real(rk) :: slip_velocity = 1.0e-4_rk
        !> Normal damping alpha (s/m) of Hunt and Crossley's law (rs_contact_obstacle): the
        !> penalty force k delta^2 grows to k delta^2 (1 + alpha d delta / dt).
        real(rk) :: damping = 0.0_rk
        !> A moving obstacle translates by f(t) displacement (f the time function, f(0) = 0).
        real(rk) :: displacement(3) = 0.0_rk
        character(len=name_len) :: time_function = 'constant'
        real(rk) :: t_on = 0.0_rk
        real(rk) :: t_off = unset_real
        real(rk) :: table_times(max_table) = unset_real
        real(rk) :: table_values(max_table) = unset_real
    end type obstacle_input_t

    !> &sweep: one swept variable (DESIGN.md §5, §6). `parameter` is a path into the scene,
    !> 'rod(1)%EI1', 'time%dt', 'load(1)%force(3)'; its values are the leading given entries of
    !> `values`, or `linspace` / `logspace` = first, last, count. The sweeps of a scene combine
    !> in file order: 'product' forms the Cartesian product with the sweeps before it, 'zip'
    !> pairs element-wise with the sweep just before it. Validated and resolved by rs_io_sweep.
    type, public :: sweep_input_t
        !> Line of the group in the input file (set by the reader; not an input variable).
        integer :: input_line = 0
        !> The path; the resolver rewrites it in its canonical spelling ('rod(1)%EI1').
        character(len=name_len) :: parameter = ''
        real(rk) :: values(max_sweep_values) = unset_real
        real(rk) :: linspace(3) = unset_real
        real(rk) :: logspace(3) = unset_real
        character(len=name_len) :: mode = 'product'
        !> The swept variable is an integer, so the values are whole numbers, rounded from
        !> round-off (set by the resolver; not an input variable).
        logical :: integral = .false.
    end type sweep_input_t

    !> A whole scene: the single groups and the repeatable ones in file order.
    !> &modes: modal analysis (issue 27 item 1, docs/theory/modes.md): the lowest modes of
    !> the linearized equations of motion about a state at rest, after the run.
    type, public :: modes_input_t
        !> The group was given (set by the reader; not an input variable): modes are computed.
        logical :: given = .false.
        integer :: input_line = 0
        !> Number of modes (rigid-body modes included), lowest first.
        integer :: n_modes = 10
        !> The state the equations are linearized about: 'reference' (the initial state, loads
        !> of t = 0) or 'equilibrium' (the end state of a quasistatic run, with the loads of
        !> its load time: t_end, or a continuation's last point's).
        character(len=16) :: about = 'reference'
        !> What is computed: 'modes' (frequencies) or 'buckling' (the critical load factors of
        !> the run's loads about the reference state, issue 27 item 2).
        character(len=16) :: kind = 'modes'
    end type modes_input_t

    type, public :: scene_t
        character(len=:), allocatable :: source_file
        character(len=:), allocatable :: source_text
        type(run_input_t) :: run
        type(time_input_t) :: time
        type(solver_input_t) :: solver
        type(output_input_t) :: output
        type(rod_input_t), allocatable :: rods(:)
        type(bc_input_t), allocatable :: bcs(:)
        type(load_input_t), allocatable :: loads(:)
        type(actuator_input_t), allocatable :: actuators(:)
        type(joint_input_t), allocatable :: joints(:)
        type(plate_input_t), allocatable :: plates(:)
        type(contact_input_t) :: contact
        type(obstacle_input_t), allocatable :: obstacles(:)
        type(sweep_input_t), allocatable :: sweeps(:)
        type(segment_input_t), allocatable :: segments(:)
        type(modes_input_t) :: modes
    end type scene_t

contains

    !> i if `v` is parallel to the i-th coordinate axis (its other components below 1e-12 |v|),
    !> else 0 (a sliding end's axis in a formulation that holds coordinates).
    pure integer function coordinate_axis(v) result(i)
        real(rk), intent(in) :: v(3)
        integer :: k
        k = maxloc(abs(v), dim=1)
        i = 0
        if (all(abs(v(pack([1, 2, 3], [1, 2, 3] /= k))) <= 1.0e-12_rk * norm2(v)) .and. &
            v(k) /= 0.0_rk) i = k
    end function coordinate_axis

    !> The rod has Kelvin-Voigt viscosity or external drag (given and not zero; before or
    !> after resolve_kelvin_voigt).
    pure logical function rod_is_damped(rod)
        type(rod_input_t), intent(in) :: rod
        rod_is_damped = any(rod%kelvin_voigt_time /= 0.0_rk .and. &
            rod%kelvin_voigt_time /= unset_real) .or. rod%drag /= 0.0_rk .or. &
            rod%angular_drag /= 0.0_rk
    end function rod_is_damped

    !> Number of &segment groups of `scene` on the rod named `rod_name`.
    pure integer function rod_segment_count(scene, rod_name) result(n)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: rod_name
        n = 0
        if (allocated(scene%segments)) n = count(scene%segments%rod == rod_name)
    end function rod_segment_count

    !> The section-derived values (section_derived_names: EA, GA1, GA2, EI1, EI2, GJ, rhoA,
    !> rhoI1, rhoI2) of each of the n_elements equal elements of the resolved rod `rod`: those
    !> of the &segment of the rod whose interval holds the element's midpoint, else the rod's.
    !> The resolver puts every s_end on a node, so the midpoint names the one segment of the
    !> whole element; with another element count (a sizing estimate) it is the nearest. The
    !> values are per unit arc length of the given geometry: a prestrained rod's are scaled
    !> from its stress-free ones (below).
    pure function element_properties(scene, rod, n_elements) result(values)
        type(scene_t), intent(in) :: scene
        type(rod_input_t), intent(in) :: rod
        integer, intent(in) :: n_elements
        real(rk) :: values(9, n_elements)
        values = spread([rod%EA, rod%GA1, rod%GA2, rod%EI1, rod%EI2, rod%GJ, rod%rhoA, &
            rod%rhoI1, rod%rhoI2], 2, n_elements)
        if (allocated(scene%segments)) call segment_properties(scene, rod, values)
        ! A prestrained rod (&rod prestrain) in the arc length s of its given geometry, s =
        ! (1 + prestrain) S with S the stress-free one (docs/theory/prestretched_starts.md):
        ! every stiffness per unit s is (1 + prestrain) times the stress-free one, every inertia
        ! per unit s divided by it (the mass is that of the stress-free length). Values not
        ! given (a quasistatic rod's inertias) stay unset.
        if (rod%prestrain == 0.0_rk) return
        where (values(1:6, :) /= unset_real) values(1:6, :) = (1.0_rk + rod%prestrain) * &
            values(1:6, :)
        where (values(7:9, :) /= unset_real) values(7:9, :) = values(7:9, :) / &
            (1.0_rk + rod%prestrain)
    end function element_properties

    !> The reference axial (force) strain Gamma_0 . d_3 per unit arc length s of the given
    !> geometry of a prestrained rod, 1 / (1 + prestrain) (docs/theory/prestretched_starts.md):
    !> with element_properties' stiffnesses it makes the energy per unit s that of the
    !> stress-free rod; the shear and bending references stay those of the given geometry.
    pure real(rk) function axial_reference(rod)
        type(rod_input_t), intent(in) :: rod
        axial_reference = 1.0_rk / (1.0_rk + rod%prestrain)
    end function axial_reference

    !> Whether a support with release time `release_time` (&bc release_time; unset_real: never)
    !> holds its end: in a time step from t_n of length h, until the step's midpoint passes the
    !> release (a release on the time grid frees the end from the first step that starts
    !> there); in an equilibrium at load time t (`static`), while t <= release_time, so the
    !> initial equilibrium holds an end released at t = 0 (docs/theory/prestretched_starts.md).
    pure logical function end_is_held(release_time, t_n, h, static)
        real(rk), intent(in) :: release_time, t_n, h
        logical, intent(in) :: static
        if (release_time == unset_real) then
            end_is_held = .true.
        else if (static) then
            end_is_held = t_n <= release_time
        else
            end_is_held = t_n + 0.5_rk * h < release_time
        end if
    end function end_is_held

    !> The values of the &segment groups of `rod` over those of the rod (element_properties).
    pure subroutine segment_properties(scene, rod, values)
        type(scene_t), intent(in) :: scene
        type(rod_input_t), intent(in) :: rod
        real(rk), intent(inout) :: values(:, :)
        real(rk) :: s_mid, best
        integer :: e, k, n_elements
        n_elements = size(values, 2)
        do e = 1, n_elements
            s_mid = rod%length * (real(e, rk) - 0.5_rk) / real(n_elements, rk)
            best = huge(1.0_rk)
            ! Segments of a rod are in increasing s_end (the resolver checks it): the first
            ! that ends after the midpoint holds it.
            do k = 1, size(scene%segments)
                associate (seg => scene%segments(k))
                    if (seg%rod /= rod%name .or. seg%s_end <= s_mid .or. seg%s_end >= best) cycle
                    best = seg%s_end
                    values(:, e) = segment_values_at(seg, s_mid)
                end associate
            end do
        end do
    end subroutine segment_properties

    !> The section-derived values of segment `seg` at arc length s: its resolved values, or
    !> for a taper those of the section whose dimensions are linear in s between the
    !> segment's start and end (the section formulas of rs_model_section), with the
    !> segment's directly given stiffnesses and inertias on top (constant along it).
    pure function segment_values_at(seg, s) result(values)
        type(segment_input_t), intent(in) :: seg
        real(rk), intent(in) :: s
        real(rk) :: values(9), given(9), t
        values = seg%values
        if (len_trim(seg%taper) == 0) return
        t = (s - seg%s_start) / (seg%s_end - seg%s_start)
        values = section_values(shaped_section(trim(seg%taper), (1.0_rk - t) * &
            seg%taper_dims(:, 1) + t * seg%taper_dims(:, 2)), seg%taper_material(1), &
            seg%taper_material(2), seg%taper_material(3), seg%taper_material(4), seg%saint_venant)
        given = [seg%EA, seg%GA1, seg%GA2, seg%EI1, seg%EI2, seg%GJ, seg%rhoA, seg%rhoI1, seg%rhoI2]
        where (given /= unset_real) values = given
    end function segment_values_at

    !> The inertia tensor of the body of a &bc (kind = 'body') about its centre of mass,
    !> inertial components in the reference configuration: diagonal `inertia`, off-diagonal
    !> `inertia_products` (I_yz, I_xz, I_xy).
    pure function body_inertia_tensor(bc) result(tensor)
        type(bc_input_t), intent(in) :: bc
        real(rk) :: tensor(3, 3)
        tensor = inertia_tensor(bc%inertia, bc%inertia_products)
    end function body_inertia_tensor

    !> The inertia tensor from its diagonal `inertia` (I_xx, I_yy, I_zz) and its off-diagonal
    !> `products` (I_yz, I_xz, I_xy): a body on an end, a floating plate.
    pure function inertia_tensor(inertia, products) result(tensor)
        real(rk), intent(in) :: inertia(3), products(3)
        real(rk) :: tensor(3, 3)
        tensor = 0.0_rk
        tensor(1, 1) = inertia(1)
        tensor(2, 2) = inertia(2)
        tensor(3, 3) = inertia(3)
        tensor(2, 3) = products(1)
        tensor(3, 2) = products(1)
        tensor(1, 3) = products(2)
        tensor(3, 1) = products(2)
        tensor(1, 2) = products(3)
        tensor(2, 1) = products(3)
    end function inertia_tensor


    !> Number of steps of the scene's time grid, max(1, ceiling(t_end / dt)) as the run takes
    !> them (the last one may be shorter). The quotient is taken in reals and capped at the
    !> largest default integer, which the input check refuses (a 32-bit ceiling of 2.2e9 was
    !> one step); never more steps than that are numbered.
    pure integer function step_count(scene)
        type(scene_t), intent(in) :: scene
        real(rk) :: steps
        if (trim(scene%time%continuation) == 'arc_length') then
            step_count = scene%time%path_steps
            return
        end if
        steps = scene%time%t_end / scene%time%dt - 1.0e-9_rk
        step_count = max(1, ceiling(min(steps, real(huge(1), rk) - 1.0_rk)))
    end function step_count

    !> The time of the record after step n: n dt (t_end for the last step), or the step number
    !> of an arc-length continuation, whose load time is a series of its own.
    pure real(rk) function record_time(scene, n)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n
        if (trim(scene%time%continuation) == 'arc_length') then
            record_time = real(n, rk)
        else
            record_time = min(real(n, rk) * scene%time%dt, scene%time%t_end)
        end if
    end function record_time

    !> True if `load` acts on the rod named `rod_name`: it names that rod, or it is gravity
    !> without a rod (gravity on every rod).
    pure logical function load_applies_to(load, rod_name)
        type(load_input_t), intent(in) :: load
        character(len=*), intent(in) :: rod_name
        load_applies_to = trim(load%rod) == trim(rod_name) .or. &
            (len_trim(load%rod) == 0 .and. trim(load%where) == 'gravity')
    end function load_applies_to

    !> Number of values of `sweep`: the count of linspace or logspace, else the number of
    !> leading given entries of values.
    pure integer function sweep_value_count(sweep) result(n)
        type(sweep_input_t), intent(in) :: sweep
        if (all(sweep%linspace /= unset_real)) then
            n = nint(sweep%linspace(3))
        else if (all(sweep%logspace /= unset_real)) then
            n = nint(sweep%logspace(3))
        else
            n = 0
            do while (n < max_sweep_values)
                if (sweep%values(n + 1) == unset_real) exit
                n = n + 1
            end do
        end if
    end function sweep_value_count

    !> The values of a valid `sweep`, in order: as given, or evenly (linspace) or geometrically
    !> (logspace) spaced from first to last, both ends exact; whole numbers for an integral
    !> sweep.
    pure function sweep_values(sweep) result(values)
        type(sweep_input_t), intent(in) :: sweep
        real(rk), allocatable :: values(:)
        real(rk) :: first, last
        integer :: n, j
        n = sweep_value_count(sweep)
        allocate(values(n))
        if (all(sweep%linspace /= unset_real)) then
            first = sweep%linspace(1)
            last = sweep%linspace(2)
            ! (last - first) (j - 1) first, then the division: exact where the grid is whole.
            do j = 1, n
                values(j) = first + (last - first) * real(j - 1, rk) / real(n - 1, rk)
            end do
            values(n) = last
        else if (all(sweep%logspace /= unset_real)) then
            first = sweep%logspace(1)
            last = sweep%logspace(2)
            do j = 1, n
                values(j) = first * exp(log(last / first) * real(j - 1, rk) / real(n - 1, rk))
            end do
            values(1) = first
            values(n) = last
        else
            values = sweep%values(1:n)
        end if
        if (sweep%integral) values = anint(values)
    end function sweep_values

    !> Number of members of the sweeps of `scene` (0 without &sweep): the product of the value
    !> counts of the blocks, a block being a sweep with the 'zip' sweeps that follow it.
    pure integer function sweep_member_count(scene) result(n)
        type(scene_t), intent(in) :: scene
        integer :: s
        n = 0
        if (.not. allocated(scene%sweeps)) return
        if (size(scene%sweeps) == 0) return
        n = 1
        do s = 1, size(scene%sweeps)
            if (s > 1 .and. trim(scene%sweeps(s)%mode) == 'zip') cycle
            n = n * sweep_value_count(scene%sweeps(s))
        end do
    end function sweep_member_count

    !> The value index of each of `sweeps` in member `id` (1-based): nested loops over the
    !> blocks in file order, the first block varying slowest; the sweeps of a block ('zip')
    !> take the same index.
    pure function sweep_member_indices(sweeps, id) result(indices)
        type(sweep_input_t), intent(in) :: sweeps(:)
        integer, intent(in) :: id
        integer :: indices(size(sweeps))
        integer :: s, rest, n
        rest = id - 1
        do s = size(sweeps), 1, -1
            if (s > 1 .and. trim(sweeps(s)%mode) == 'zip') cycle
            n = sweep_value_count(sweeps(s))
            indices(s) = mod(rest, n) + 1
            rest = rest / n
        end do
        ! A zip sweep takes the index of the block it joins (the nearest product sweep before it).
        do s = 2, size(sweeps)
            if (trim(sweeps(s)%mode) == 'zip') indices(s) = indices(s - 1)
        end do
    end function sweep_member_indices

end module rs_model_scene
