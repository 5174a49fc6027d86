!> What the planar formulations (ph_planar, cl_em_planar; seed 001, methods/ph_planar.md) will
!> do for one rod of a resolved, checked scene: the plan of `rodsolve --check-input` (DESIGN.md
!> §4). Read off the scene data: the plane of the rod's system of joined rods
!> (rs_model_planarity), the scheme, the unknowns (3 per node, plus 3 element strains per
!> element for ph_planar unless condensed), the supports, the joints as shared nodal unknowns,
!> the loads and gravity in the plane, and what is skipped.
module rs_ph_planar_plan
    use rs_core_kinds, only: rk
    use rs_core_strings, only: str, vector_text, str_significant
    use rs_model_scene, only: scene_t, rod_is_damped, unset_real
    use rs_model_damping, only: damping_plan_text, kv_axial, kv_shear1, kv_shear2, kv_bend1, &
        kv_bend2
    use rs_model_units, only: unit_in_system
    use rs_model_coupling, only: coupled_systems
    use rs_model_planarity, only: plane_t, plane_of_rods, plane_text, point_in_plane, &
        vector_in_plane, angle_in_plane, cross, planar_held
    use rs_model_support, only: end_hold, mask_names
    implicit none
    private

    public :: ph_planar_plan_lines

    !> Cosine above which a director counts as along the plane normal.
    real(rk), parameter :: along = 1.0_rk - 1.0e-12_rk

contains

    !> The plan of rod `i` of `scene` (formulation ph_planar or cl_em_planar) as comment lines
    !> "!     ..." (each ending in a new line), without the rod's title line.
    subroutine ph_planar_plan_lines(scene, i, text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable, intent(out) :: text
        integer, allocatable :: system_of(:), first(:), members(:), rods(:)
        type(plane_t) :: plane
        character(len=:), allocatable :: units, m, others, formulation
        real(rk) :: t(3), d2(3)
        integer :: n_nodes, n_elements, n_fixed, n_total, k, j, normal_director
        logical :: held(3), held_ok

        text = ''
        units = trim(scene%run%units)
        m = unit_in_system('m', units)
        call coupled_systems(scene, system_of, first, members)
        rods = members(first(system_of(i)):first(system_of(i) + 1) - 1)
        plane = plane_of_rods(scene, rods)
        others = ''
        do k = 1, size(rods)
            if (rods(k) == i) cycle
            if (len(others) > 0) others = others // ', '
            others = others // '''' // trim(scene%rods(rods(k))%name) // ''''
        end do
        associate (rod => scene%rods(i))
            formulation = trim(rod%formulation)
            if (.not. plane%found) then
                call add('not planar: ' // plane%reason)
                return
            end if
            if (len(others) > 0) then
                call add('plane: ' // plane_text(plane) // ', shared with the joined rod(s) ' // others)
            else
                call add('plane: ' // plane_text(plane))
            end if
            call add('planar coordinates: x = (p - origin) . e1, y = (p - origin) . e2, e1 = (' // &
                vector_text(plane%e1) // '), e2 = (' // vector_text(plane%e2) // '), theta from e1 ' // &
                'towards e2')
            t = rod%direction
            call add('geometry: straight from (x, y) = (' // &
                vector_text(point_in_plane(plane, rod%start)) // ') ' // m // ' at theta_0 = ' // &
                str(angle_in_plane(plane, t)) // ' rad, length ' // &
                str(rod%length) // ' ' // m)
            d2 = cross(t, rod%d1)
            normal_director = 1
            if (abs(dot_product(d2, plane%normal)) >= along * norm2(d2)) normal_director = 2
            call add('section in the plane: EA = ' // str(rod%EA) // ', GA = ' // &
                str(merge(rod%GA2, rod%GA1, normal_director == 1)) // ', EI = EI' // &
                str(normal_director) // ' = ' // str(merge(rod%EI1, rod%EI2, normal_director == 1)) // &
                ' (d' // str(normal_director) // ' is the plane normal); torsion and out-of-plane ' // &
                'bending do not arise')
            n_elements = rod%n_elements
            n_nodes = n_elements + 1
            call add('mesh: ' // str(n_elements) // ' two-node elements, ' // str(n_nodes) // &
                ' nodes at equal arc length, ' // str(rod%n_gauss) // ' Gauss point(s) per element')
            ! The planar coordinates each support holds (rs_model_planarity planar_held).
            n_fixed = 0
            do j = 1, size(scene%bcs)
                ! A released support's unknowns stay (held by their own rows until then).
                if (scene%bcs(j)%rod /= rod%name .or. scene%bcs(j)%release_time /= unset_real) cycle
                call planar_held(plane, end_hold(scene%bcs(j)), held, held_ok)
                n_fixed = n_fixed + count(held)
            end do
            select case (formulation)
            case ('ph_planar')
                call add('scheme: PH-EM, the implicit midpoint rule on the port-Hamiltonian ' // &
                    'system (methods/ph_planar.md §4.3): nodal (x, y, theta), theta shifted by 2 pi k ' // &
                    'after a dynamic step when no support fixes one, ' // &
                    'and element strains (Gamma1, Gamma2, kappa); exact energy and angular momentum ' // &
                    'balance')
                if (scene%solver%condense_stresses) then
                    n_total = 3 * n_nodes
                    call add('unknowns: 3 x ' // str(n_nodes) // ' nodes (x, y, theta) = ' // &
                        str(n_total) // ', less ' // str(n_fixed) // ' fixed by supports; the 3 x ' // &
                        str(n_elements) // ' element strains are condensed per element ' // &
                        '(condense_stresses = .true., exact: §3.5)')
                else
                    n_total = 3 * n_nodes + 3 * n_elements
                    call add('unknowns: 3 x ' // str(n_nodes) // ' nodes (x, y, theta) + 3 x ' // &
                        str(n_elements) // ' elements (Gamma1, Gamma2, kappa) = ' // str(n_total) // &
                        ', less ' // str(n_fixed) // ' fixed by supports (condense_stresses = ' // &
                        '.false.)')
                end if
            case default
                if (trim(rod%em_variant) == 'ph_irreducible') then
                    call add('scheme: PH-EMi, the irreducible port-Hamiltonian scheme (methods/' // &
                        'ph_planar.md §5.2): strain history at the ' // str(rod%n_gauss) // &
                        ' Gauss point(s) of each element, no correction factors')
                else if (rod%n_gauss == 1) then
                    call add('scheme: Stander-Stein energy-momentum (methods/ph_planar.md §5.1): ' // &
                        'algorithmic strain variation with Z1, Z2; axial and shear terms at 1 ' // &
                        'Gauss point (reduced, free of shear locking); energy kept exactly, angular ' // &
                        'momentum not (Z1 /= Z2, docs/theory/ph_planar.md)')
                else
                    call add('scheme: Stander-Stein energy-momentum (methods/ph_planar.md §5.1): ' // &
                        'algorithmic strain variation with Z1, Z2; axial and shear terms at ' // &
                        str(rod%n_gauss) // ' Gauss points (full, locks in bending); energy kept exactly, ' // &
                        'angular momentum not (Z1 /= Z2, docs/theory/ph_planar.md)')
                end if
                n_total = 3 * n_nodes
                call add('unknowns: 3 x ' // str(n_nodes) // ' nodes (x, y, theta) = ' // str(n_total) // &
                    ', less ' // str(n_fixed) // ' fixed by supports; no element unknowns (nothing ' // &
                    'for condense_stresses to condense)')
            end select
            call add('supports: start ' // support_text('start') // ', end ' // support_text('end'))
            call add('joints: ' // joints_text())
            if (scene%time%quasistatic) then
                call add('mass terms: skipped (quasistatic: time is a load factor)')
            else
                call add('mass terms: rhoA = ' // &
                    str(rod%rhoA) // ' ' // unit_in_system('kg/m', units) // ', rhoI = ' // &
                    str(merge(rod%rhoI1, rod%rhoI2, normal_director == 1)) // ' ' // &
                    unit_in_system('kg m', units))
            end if
            call add('damping: ' // damping_text())
            call add('loads: ' // loads_text())
            call add('initial velocity: ' // velocity_text())
            call add('skipped: orthonormality and constraint multipliers, Maxwell branches, ' // &
                'actuators, torsion and out-of-plane motion (3D: ph_director)')
        end associate
    contains
        subroutine add(line)
            character(len=*), intent(in) :: line
            text = text // '!     ' // line // new_line('a')
        end subroutine add

        function support_text(end_name) result(t)
            character(len=*), intent(in) :: end_name
            character(len=:), allocatable :: t
            integer :: b
            t = 'free'
            do b = 1, size(scene%bcs)
                if (scene%bcs(b)%rod /= scene%rods(i)%name .or. trim(scene%bcs(b)%end) /= end_name) cycle
                select case (trim(scene%bcs(b)%kind))
                case ('clamped')
                    t = 'clamped (x, y, theta fixed)'
                case ('pinned')
                    t = 'pinned (x, y fixed, theta free)'
                case ('sliding')
                    t = 'sliding along (' // vector_text(scene%bcs(b)%axis) // ') (theta and ' // &
                        'the other coordinate fixed)'
                case ('held')
                    call planar_held(plane, end_hold(scene%bcs(b)), held, held_ok)
                    t = 'held (fixed of x, y, theta: ' // mask_names(held, [character(len=5) :: &
                        'x', 'y', 'theta']) // ')'
                end select
            end do
        end function support_text

        function joints_text() result(t)
            character(len=:), allocatable :: t
            character(len=:), allocatable :: mine, other, other_end, shared
            integer :: b
            t = ''
            if (.not. allocated(scene%joints)) return
            do b = 1, size(scene%joints)
                associate (joint => scene%joints(b))
                    if (joint%rod_a == scene%rods(i)%name) then
                        mine = trim(joint%end_a)
                        other = trim(joint%rod_b)
                        other_end = trim(joint%end_b)
                    else if (joint%rod_b == scene%rods(i)%name) then
                        mine = trim(joint%end_b)
                        other = trim(joint%rod_a)
                        other_end = trim(joint%end_a)
                    else
                        cycle
                    end if
                    if (trim(joint%kind) == 'rigid') then
                        shared = 'shared nodal x, y, theta'
                    else
                        shared = 'shared nodal x, y, own theta'
                    end if
                    if (len(t) > 0) t = t // '; '
                    t = t // '''' // mine // ''' end ' // trim(joint%kind) // ' with the ''' // &
                        other_end // ''' end of rod ''' // other // ''' (' // shared // '; &joint at ' // &
                        'line ' // str(joint%input_line) // ')'
                end associate
            end do
            if (len(t) == 0) t = 'none'
        end function joints_text

        function loads_text() result(t)
            character(len=:), allocatable :: t
            integer :: b, n_end, n_distributed
            character(len=:), allocatable :: gravity
            n_end = 0
            n_distributed = 0
            gravity = ''
            do b = 1, size(scene%loads)
                associate (load => scene%loads(b))
                    if (trim(load%where) == 'gravity') then
                        if (len_trim(load%rod) > 0 .and. load%rod /= scene%rods(i)%name) cycle
                        if (len(gravity) > 0) gravity = gravity // ' and '
                        gravity = gravity // 'g = (' // vector_text(vector_in_plane(plane, &
                            load%acceleration)) // ') ' // unit_in_system('m/s^2', units)
                    else if (load%rod == scene%rods(i)%name) then
                        if (trim(load%where) == 'distributed') then
                            n_distributed = n_distributed + 1
                        else
                            n_end = n_end + 1
                        end if
                    end if
                end associate
            end do
            t = str(n_end) // ' end load(s), ' // str(n_distributed) // ' distributed (dead, ' // &
                'in-plane force and moment about the normal)'
            if (len(gravity) > 0) then
                t = t // ', gravity ' // gravity // ' in the plane, as the distributed force rhoA g'
            else
                t = t // ', no gravity'
            end if
        end function loads_text

        !> damping_plan_text and, for a damped rod, what the plane takes of it
        !> (docs/theory/ph_planar.md "Damping").
        function damping_text() result(t)
            character(len=:), allocatable :: t
            integer :: kv(3)
            associate (input => scene%rods(i))
                t = damping_plan_text(input)
                if (.not. rod_is_damped(input)) return
                if (normal_director == 1) then
                    kv = [kv_axial, kv_shear2, kv_bend1]
                else
                    kv = [kv_axial, kv_shear1, kv_bend2]
                end if
                t = t // '; in the plane: Kelvin-Voigt times (EA, GA' // str(3 - normal_director) // &
                    ', EI' // str(normal_director) // ') = (' // &
                    str_significant(input%kelvin_voigt_time(kv(1)), 4) // ', ' // &
                    str_significant(input%kelvin_voigt_time(kv(2)), 4) // ', ' // &
                    str_significant(input%kelvin_voigt_time(kv(3)), 4) // ') s on the step''s ' // &
                    'strain increments; drag against (x'', y'') and angular drag against theta'' ' // &
                    'at the step''s midpoint velocities; the dissipation is booked in the energy ' // &
                    'balance'
            end associate
        end function damping_text

        function velocity_text() result(t)
            character(len=:), allocatable :: t
            associate (input => scene%rods(i))
                if (all(input%velocity == 0.0_rk) .and. all(input%angular_velocity == 0.0_rk)) then
                    t = 'at rest'
                else
                    t = 'rigid motion in the plane: (vx, vy) = (' // &
                        vector_text(vector_in_plane(plane, input%velocity)) // ') ' // &
                        unit_in_system('m/s', units) // ', theta'' = ' // &
                        str(dot_product(input%angular_velocity, plane%normal)) // ' ' // &
                        unit_in_system('rad/s', units) // ' about (' // &
                        vector_text(point_in_plane(plane, input%rotation_center)) // ')'
                end if
            end associate
        end function velocity_text
    end subroutine ph_planar_plan_lines

end module rs_ph_planar_plan
