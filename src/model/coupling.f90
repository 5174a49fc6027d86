!> Which rods a scene couples (DESIGN.md §4, §5): rods tied by &joint groups, and the rods of
!> one &plate, form one system that is solved as a whole; with &contact every rod may touch
!> every other, so all rods of the scene form one system. Every other rod is a system of its
!> own. The systems are numbered by their first rod, so a scene without joints, plates and
!> contact has system i = rod i.
module rs_model_coupling
    use rs_core_kinds, only: rk
    use rs_model_scene, only: scene_t
    implicit none
    private

    public :: coupled_systems, system_costs

contains

    !> system_of(i): the system of rod i (1..n_systems); members(first(k):first(k+1)-1) are the
    !> rods of system k in rod order (the first one leads the system).
    pure subroutine coupled_systems(scene, system_of, first, members)
        type(scene_t), intent(in) :: scene
        integer, allocatable, intent(out) :: system_of(:), first(:), members(:)
        integer :: parent(size(scene%rods)), i, j, a, b, n_rods, n_systems, k, at, lead
        n_rods = size(scene%rods)
        parent = [(i, i = 1, n_rods)]
        ! Union of the two rods of every joint and of the rods of every plate (the smaller index
        ! is the root); contact ties every rod to the first.
        if (allocated(scene%joints)) then
            do j = 1, size(scene%joints)
                call unite(parent, rod_named(scene%joints(j)%rod_a), rod_named(scene%joints(j)%rod_b))
            end do
        end if
        if (allocated(scene%plates)) then
            do j = 1, size(scene%plates)
                lead = 0
                do k = 1, size(scene%plates(j)%rods)
                    b = rod_named(scene%plates(j)%rods(k))
                    if (b == 0) cycle
                    if (lead == 0) lead = b
                    call unite(parent, lead, b)
                end do
            end do
        end if
        if (scene%contact%given) then
            do i = 2, n_rods
                call unite(parent, 1, i)
            end do
        end if
        allocate(system_of(n_rods))
        n_systems = 0
        do i = 1, n_rods
            a = root(i)
            if (a == i) then
                n_systems = n_systems + 1
                system_of(i) = n_systems
            else
                system_of(i) = system_of(a)
            end if
        end do
        allocate(first(n_systems + 1), members(n_rods))
        at = 1
        do k = 1, n_systems
            first(k) = at
            do i = 1, n_rods
                if (system_of(i) /= k) cycle
                members(at) = i
                at = at + 1
            end do
        end do
        first(n_systems + 1) = at
    contains
        !> Join the systems of rods r and s in the forest `forest` (the host's parent; passed,
        !> as a pure procedure may not change its host's variables); 0 is an unknown name.
        pure subroutine unite(forest, r, s)
            integer, intent(inout) :: forest(:)
            integer, intent(in) :: r, s
            integer :: ra, rb
            ra = root(r)
            rb = root(s)
            if (ra == 0 .or. rb == 0) return
            forest(max(ra, rb)) = min(ra, rb)
        end subroutine unite

        pure integer function root(i)
            integer, intent(in) :: i
            root = i
            if (root == 0) return
            do while (parent(root) /= root)
                root = parent(root)
            end do
        end function root

        pure integer function rod_named(name)
            character(len=*), intent(in) :: name
            integer :: r
            rod_named = 0
            if (len_trim(name) == 0) return
            do r = 1, n_rods
                if (trim(scene%rods(r)%name) == trim(name)) then
                    rod_named = r
                    return
                end if
            end do
        end function rod_named
    end subroutine coupled_systems

    !> Estimated cost of a step of each system (first, members as from coupled_systems): the
    !> nodes of its rods, n_elements * degree + 1 each, as the unknowns grow with them. Used to
    !> deal systems to ranks (rs_parallel_deal); the time steps are the scene's, the same for all.
    pure function system_costs(scene, first, members) result(cost)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: first(:), members(:)
        real(rk) :: cost(size(first) - 1)
        integer :: k, m
        cost = 0.0_rk
        do k = 1, size(first) - 1
            do m = first(k), first(k + 1) - 1
                associate (rod => scene%rods(members(m)))
                    cost(k) = cost(k) + real(max(rod%n_elements, 1) * max(rod%degree, 1) + 1, rk)
                end associate
            end do
        end do
    end function system_costs

end module rs_model_coupling
