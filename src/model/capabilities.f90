!> What each formulation can do: the capability matrix of DESIGN.md §1 as data, so that
!> `--check-input` rejects a scene that asks a formulation for more than it has and
!> docs/user/capabilities.md can be checked against it. A formulation that is not available in
!> this build has an empty row.
module rs_model_capabilities
    implicit none
    private

    public :: capability_of, lists_name, end_kinds_at

    !> The formulations with a row, in the order of docs/user/capabilities.md.
    character(len=*), parameter, public :: formulation_names(5) = [character(len=12) :: &
        'ph_director', 'ph_planar', 'cl_em_planar', 'se3_pg', 'se3_strand']

    !> One row of the matrix. Lists are '|'-separated names, empty when nothing is supported.
    type, public :: capability_t
        character(len=32) :: formulation = ''
        logical :: available = .false.
        !> Kinds of &bc it can apply at an end ('clamped', 'pinned', 'free', 'driven').
        character(len=64) :: end_kinds = ''
        !> Kinds of &bc it can apply at the end s = L (&bc end = 'end'), where that differs from
        !> the end s = 0; blank = the same as end_kinds.
        character(len=64) :: end_kinds_at_end = ''
        character(len=64) :: load_places = ''
        character(len=64) :: load_frames = ''
        !> Kinematic constraints (&rod constraint) it can enforce.
        character(len=64) :: constraints = ''
        !> Quasistatic runs (&time quasistatic = .true.).
        logical :: quasistatic = .false.
        !> Generalized-Maxwell branches (&rod maxwell_*).
        logical :: viscoelastic = .false.
        !> Pneumatic chambers and tendons (&actuator).
        logical :: actuation = .false.
        !> A curved stress-free reference (&rod geometry = 'helix' or 'polyline').
        logical :: curved_reference = .false.
        !> A straight stress-free shape under a curved initial one (&rod prestressed).
        logical :: prestressed = .false.
        !> Kinds of &joint it can tie its rods' ends with ('revolute', 'rigid', 'spherical').
        character(len=64) :: joints = ''
        !> Rod ends tied to rigid end plates, fixed or driven (&plate).
        logical :: end_plates = .false.
        !> Rod-rod and self contact (&contact).
        logical :: contact = .false.
        !> A planar formulation: its rods and everything acting on them must lie in one plane
        !> (rs_model_planarity).
        logical :: planar = .false.
        !> Statics by damped dynamics (&time relaxation = .true.).
        logical :: relaxation = .false.
        !> How a driven end (&bc kind = 'driven') is prescribed: 'pose' (displacement and
        !> rotation), 'velocity' (velocity and angular_velocity; several &bc on one end add
        !> up), or blank when it has no driven ends.
        character(len=16) :: drive = ''
    end type capability_t

contains

    !> The row of formulation `name` (an unavailable row if the name is unknown).
    pure function capability_of(name) result(row)
        character(len=*), intent(in) :: name
        type(capability_t) :: row
        row%formulation = name
        select case (trim(name))
        case ('ph_director')
            ! seed 000 §2.9 and §6.1: clamped (Dirichlet) and free (Neumann) ends; dead end
            ! loads, distributed loads and gravity. The extensions of seed 000 §5
            ! (methods/ph_director_3d.md §2.3, §3, §6.3): shear-rigid and inextensible
            ! constraints, quasistatics, Maxwell branches, actuators; and a curved stress-free
            ! reference (the reference strains at the Gauss points, docs/theory/ph_director.md).
            ! Bundles (issue 10, DESIGN.md §5): rigid, spherical and revolute joints and end
            ! plates as constraints with multipliers on the end nodes (rs_ph_director_tie), and
            ! rod-rod and self contact by an energy-consistent penalty (rs_contact_potential).
            row = capability_t(formulation='ph_director', available=.true., end_kinds='clamped|free', &
                load_places='start|end|distributed|gravity', load_frames='spatial', &
                constraints='none|kirchhoff|inextensible', quasistatic=.true., viscoelastic=.true., &
                actuation=.true., curved_reference=.true., prestressed=.true., &
                joints='rigid|spherical|revolute', end_plates=.true., contact=.true.)
        case ('ph_planar', 'cl_em_planar')
            ! seed 001 (methods/ph_planar.md §2.5, §5, §6.3): straight planar rods with
            ! clamped, pinned (ground pin: position fixed, angle free) and free ends; dead end
            ! loads, distributed loads and gravity in the plane; quasistatics (§4.7); revolute
            ! joints as shared nodal positions (§6.3) and rigid joints as shared positions and
            ! angles.
            row = capability_t(formulation=trim(name), available=.true., &
                end_kinds='clamped|pinned|free', load_places='start|end|distributed|gravity', &
                load_frames='spatial', constraints='none', quasistatic=.true., &
                viscoelastic=.false., actuation=.false., curved_reference=.false., &
                joints='revolute|rigid', planar=.true.)
        case ('se3_pg')
            ! seed 002 (methods/se3_petrov_galerkin.md §3.4, §7, §10): clamped and pinned ends
            ! by elimination, dead and follower end loads, dead distributed loads and gravity,
            ! statics (&time quasistatic) and midpoint dynamics; any reference the SE(3)
            ! interpolation represents.
            row = capability_t(formulation='se3_pg', available=.true., end_kinds='clamped|pinned|free|driven', &
                load_places='start|end|distributed|gravity', load_frames='spatial|follower', &
                constraints='none', quasistatic=.true., viscoelastic=.false., actuation=.false., &
                curved_reference=.true., joints='', planar=.false., drive='pose')
        case ('se3_strand')
            ! seed 004 (methods/se3_strands.md §2.5, §2.7, §3.4, §3.7): motion prescribed at
            ! s = 0 (a clamp, or a driven end whose velocity is prescribed, P0 = M V0(t)) and
            ! stress at s = L (free, with its end load); drag, gravity and follower tip loads;
            ! any relaxed (curved) reference shape; statics by damped dynamics instead of
            ! quasistatics. Its damping is its own (&rod external_damping, internal_damping,
            ! kelvin_voigt_time), not Maxwell branches.
            row = capability_t(formulation='se3_strand', available=.true., &
                end_kinds='clamped|driven', end_kinds_at_end='free', &
                load_places='end|distributed|gravity', load_frames='spatial|follower', &
                constraints='none', quasistatic=.false., viscoelastic=.false., actuation=.false., &
                curved_reference=.true., prestressed=.true., joints='', planar=.false., &
                relaxation=.true., drive='velocity')
        end select
    end function capability_of

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
