!> What a formulation can do: one row of the capability matrix of DESIGN.md §1 as data, so that
!> `--check-input` rejects a scene that asks a formulation for more than it has and
!> docs/user/capabilities.md is generated from it. The rows themselves are in the formulations'
!> descriptors (src/formulations/<name>/<name>_descriptor.f90, listed by
!> rs_formulations_registry); an unknown formulation has an empty, unavailable row.
module rs_model_capabilities
    implicit none
    private

    public :: lists_name, end_kinds_at

    !> One row of the matrix. Lists are '|'-separated names, empty when nothing is supported.
    type, public :: capability_t
        character(len=32) :: formulation = ''
        logical :: available = .false.
        !> Kinds of &bc it can apply at an end ('clamped', 'pinned', 'free', 'driven', 'body',
        !> 'sliding', 'held').
        character(len=64) :: end_kinds = ''
        !> Kinds of &bc it can apply at the end s = L (&bc end = 'end'), where that differs from
        !> the end s = 0; blank = the same as end_kinds.
        character(len=64) :: end_kinds_at_end = ''
        !> Why the ends differ, appended to the messages about them ('; ...'), or blank.
        character(len=160) :: end_kinds_note = ''
        !> A held end (&bc kind = 'held') can hold the twist alone (hold = 'twist': the rotation
        !> about the end's axis, the end free to bend; rs_model_support).
        logical :: held_twist = .false.
        character(len=64) :: load_places = ''
        character(len=64) :: load_frames = ''
        !> Kinematic constraints (&rod constraint) it can enforce.
        character(len=64) :: constraints = ''
        !> Quasistatic runs (&time quasistatic = .true.).
        logical :: quasistatic = .false.
        !> Generalized-Maxwell branches (&rod maxwell_*).
        logical :: viscoelastic = .false.
        !> Kelvin-Voigt viscous stress and external drag (&rod kelvin_voigt_time, drag,
        !> angular_drag; docs/theory/damping.md).
        logical :: damping = .false.
        !> Rods that vary along their length: piecewise sections, materials, stiffnesses and
        !> inertias per element (&segment; issue 26 item 5).
        logical :: segments = .false.
        !> Pneumatic chambers and tendons (&actuator).
        logical :: actuation = .false.
        !> A curved stress-free reference (&rod geometry = 'helix', 'polyline' or 'curvature':
        !> rest curvature and pre-twist as functions of s).
        logical :: curved_reference = .false.
        !> A straight stress-free shape under a curved initial one (&rod prestressed).
        logical :: prestressed = .false.
        !> Prestretched starts (issue 26 item 3; docs/theory/prestretched_starts.md): an axial
        !> prestrain of the given geometry (&rod prestrain), a dynamic run that starts from its
        !> static equilibrium (&time initial_equilibrium), a support released at a time (&bc
        !> release_time).
        logical :: prestrain = .false.
        logical :: initial_equilibrium = .false.
        logical :: release = .false.
        !> Kinds of &joint it can tie its rods' ends with ('revolute', 'rigid', 'spherical').
        character(len=64) :: joints = ''
        !> Rod ends tied to rigid end plates, fixed or driven (&plate).
        logical :: end_plates = .false.
        !> A plate with a mass floats: a rigid body moved by its rods (&plate mass; issue 24).
        logical :: floating_plates = .false.
        !> Rod-rod and self contact (&contact).
        logical :: contact = .false.
        !> A planar formulation: its rods and everything acting on them must lie in one plane
        !> (rs_model_planarity).
        logical :: planar = .false.
        !> Statics by damped dynamics (&time relaxation = .true.).
        logical :: relaxation = .false.
        !> Its step is symmetric, so Suzuki's composition of it is of order 4 (&time order = 4;
        !> docs/theory/time_integration.md).
        logical :: order_4 = .false.
        !> Error-controlled steps (&time adaptive): a Newton-based step whose state is smooth in
        !> time, so that divided differences of it estimate the local error.
        logical :: adaptive = .false.
        !> Dynamics with the generalized-alpha scheme (&time scheme = 'generalized_alpha').
        logical :: generalized_alpha = .false.
        !> How a driven end (&bc kind = 'driven') is prescribed: 'pose' (displacement and
        !> rotation), 'velocity' (velocity and angular_velocity; several &bc on one end add
        !> up), or blank when it has no driven ends.
        character(len=16) :: drive = ''
        !> Modal analysis (&modes; docs/theory/modes.md): its dynamic step's Jacobian at rest
        !> is the linearized equations of motion (formulation_traits_t%modal_form).
        logical :: modes = .false.
        !> Modes of damped rods too (a pencil that solves them: the first-order form's damping
        !> is in A; se3_pg's damped quadratic pencil is not solved yet).
        logical :: damped_modes = .false.
        !> Linearized buckling (&modes kind = 'buckling'): a tangent stiffness to read
        !> (rs_system_linearization's buckling_stiffness: the Jacobian of the static problem,
        !> or one long step of a second-order pencil).
        logical :: buckling = .false.
        !> Arc-length continuation of its statics (&time continuation = 'arc_length';
        !> docs/theory/continuation.md): a static problem at any load time
        !> (rod_system_t%set_load_problem) with path weights.
        logical :: continuation = .false.
    end type capability_t

contains

    !> The kinds of &bc that `row` can apply at end `end_name` ('start' or 'end').
    pure function end_kinds_at(row, end_name) result(kinds)
        type(capability_t), intent(in) :: row
        character(len=*), intent(in) :: end_name
        character(len=:), allocatable :: kinds
        kinds = trim(row%end_kinds)
        if (trim(end_name) == 'end' .and. len_trim(row%end_kinds_at_end) > 0) &
            kinds = trim(row%end_kinds_at_end)
    end function end_kinds_at

    !> True if `name` is one of the '|'-separated names in `list` (a blank name, or one that
    !> contains '|', is never listed).
    pure logical function lists_name(list, name)
        character(len=*), intent(in) :: list, name
        lists_name = len_trim(name) > 0 .and. index(name, '|') == 0 .and. &
            index('|' // trim(list) // '|', '|' // trim(name) // '|') > 0
    end function lists_name

end module rs_model_capabilities
