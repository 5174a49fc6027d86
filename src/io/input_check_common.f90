!> What the checks of a resolved scene share (rs_io_input_check and the modules it calls): the
!> "file:line: " prefix of a message, rods by name, where capability messages send the reader.
module rs_io_input_check_common
    use rs_core_kinds, only: rk
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t, unset_real
    implicit none
    private

    public :: at, rod_index, rod_names, leading_count

    !> Where capability messages send the reader.
    character(len=*), parameter, public :: see_matrix = ' (docs/user/capabilities.md)'

contains

    pure function at(scene, line) result(prefix)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: line
        character(len=:), allocatable :: prefix
        if (line > 0) then
            prefix = scene%source_file // ':' // str(line) // ': '
        else
            prefix = scene%source_file // ': '
        end if
    end function at


    integer function rod_index(scene, name)
        type(scene_t), intent(in) :: scene
        character(len=*), intent(in) :: name
        integer :: i
        rod_index = 0
        do i = 1, size(scene%rods)
            if (trim(scene%rods(i)%name) == trim(name)) then
                rod_index = i
                return
            end if
        end do
    end function rod_index


    function rod_names(scene) result(text)
        type(scene_t), intent(in) :: scene
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(scene%rods)
            if (i > 1) text = text // ', '
            text = text // '''' // trim(scene%rods(i)%name) // ''''
        end do
    end function rod_names

    !> Number of leading given entries of `values`.
    pure integer function leading_count(values) result(n)
        real(rk), intent(in) :: values(:)
        n = 0
        do while (n < size(values))
            if (values(n + 1) == unset_real) exit
            n = n + 1
        end do
    end function leading_count

end module rs_io_input_check_common
