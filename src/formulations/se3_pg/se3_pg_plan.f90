!> The --check-input plan of an se3_pg rod (DESIGN.md §4; rs_formulations_plan prints it): the
!> element, the unknowns, statics or dynamics, supports and loads, and what is skipped.
module rs_se3_pg_plan
    use rs_core_strings, only: str, vector_text
    use rs_model_scene, only: scene_t, load_applies_to, rod_is_damped, unset_real
    use rs_model_support, only: end_hold_t, end_hold, held_coordinates, held_names
    use rs_model_damping, only: damping_plan_text
    use rs_model_rod_geometry, only: centreline_text
    implicit none
    private

    public :: se3_pg_plan_lines

contains

    !> '!' lines (each ending in a new line) of rod `i`.
    function se3_pg_plan_lines(scene, i) result(lines)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: lines
        character(len=:), allocatable :: supports
        type(end_hold_t) :: hold
        logical :: mask(6), ok
        integer :: j, n_nodes, n_fixed, n_follower, n_dead
        associate (rod => scene%rods(i))
            n_nodes = rod%n_elements + 1
            lines = ''
            call add('element: ' // str(rod%n_elements) // ' two-node SE(3) Petrov-Galerkin ' // &
                'elements (methods/se3_petrov_galerkin.md §5): relative-twist interpolation, ' // &
                'constant strains per element, 2 Gauss points; degree and n_gauss do not apply')
            call add('geometry: ' // centreline_text(rod, trim(scene%run%units)))
            call add('reference: stress-free initial geometry (the relative twist of each ' // &
                'element''s two nodal poses over its length is its reference strain, methods §5.3)')
            n_fixed = 0
            supports = ''
            do j = 1, size(scene%bcs)
                if (trim(scene%bcs(j)%rod) /= trim(rod%name)) cycle
                ! What the support holds (rs_model_support): its coordinates are not unknowns;
                ! a released support's unknowns stay (held by their own rows until then).
                hold = end_hold(scene%bcs(j))
                call held_coordinates(end_hold_t(hold%position, hold%rotation), mask, ok)
                ! The twist alone: one component of psi (se3_pg's twist_coordinate).
                if (hold%twist) mask(4) = .true.
                if (scene%bcs(j)%release_time == unset_real) n_fixed = n_fixed + count(mask)
                supports = supports // ' ' // trim(scene%bcs(j)%end) // ' ' // trim(scene%bcs(j)%kind)
                if (trim(scene%bcs(j)%kind) == 'sliding') supports = supports // ' along (' // &
                    vector_text(scene%bcs(j)%axis) // ')'
                if (trim(scene%bcs(j)%kind) == 'held') supports = supports // ' (' // &
                    held_names(mask) // ')'
            end do
            call add('unknowns: 6 x ' // str(n_nodes) // ' nodes (position, rotation vector) = ' // &
                str(6 * n_nodes) // ', less ' // str(n_fixed) // ' fixed by supports;' // supports)
            if (trim(scene%time%continuation) == 'arc_length') then
                call add('statics: Newton at the points of the arc-length path (the load ' // &
                    'time an unknown, above; methods §7.2 for the equilibrium); complement ' // &
                    'rotation vectors after each path step')
            else if (scene%time%quasistatic) then
                call add('statics: Newton at each load factor t (methods §7.2), full steps, ' // &
                    'increments halved on failure; complement rotation vectors after each increment')
            else if (trim(scene%time%scheme) == 'generalized_alpha') then
                call add('dynamics: generalized-alpha (Jansen, Whiting & Hulbert 2000; methods §7.3) ' // &
                    'on q'' = B(q) u, M u'' = f with rho_inf = ' // &
                    str(scene%time%rho_inf) // ', the equations at the stage ' // &
                    't_n + alpha_f h, u eliminated; the history q'', u'' in the state (24 numbers ' // &
                    'per node), the initial one from the equations at t = 0; complement rotation ' // &
                    'vectors beyond 1.25 pi after each step; numerical dissipation of the high ' // &
                    'frequencies by design (the energy balance shows it with the element''s error)')
            else
                call add('dynamics: implicit midpoint rule on q'' = B(q) u, M u'' = f (methods §7.4), ' // &
                    'u eliminated; complement rotation vectors after each step; the energy balance ' // &
                    'measures the scheme''s energy error (not exact for this element)')
            end if
            n_follower = 0
            n_dead = 0
            do j = 1, size(scene%loads)
                if (.not. load_applies_to(scene%loads(j), rod%name)) cycle
                if (trim(scene%loads(j)%frame) == 'follower') then
                    n_follower = n_follower + 1
                else
                    n_dead = n_dead + 1
                end if
            end do
            call add('loads: ' // str(n_dead) // ' dead, ' // str(n_follower) // ' follower ' // &
                '(their tangents enter Newton)')
            if (rod_is_damped(rod)) call add('damping: ' // damping_plan_text(rod) // &
                ' (docs/theory/se3_pg.md "Damping": the Kelvin-Voigt stress of the objective ' // &
                'strain rate, the drag of the step''s velocities; booked as dissipated)')
            call add('skipped: constraints, Maxwell branches, actuators, joints')
        end associate
    contains
        subroutine add(line)
            character(len=*), intent(in) :: line
            lines = lines // '!     ' // line // new_line('a')
        end subroutine add
    end function se3_pg_plan_lines

end module rs_se3_pg_plan
