!> The registry of the command line: every group demstep reads, with its
!> documentation, its table of variables and its handler. The main program, the
!> help text, the template and the "known groups" message are all derived from it.
module demstep_cli_registry
  use demstep_status, only: demstep_status_type
  use demstep_namelist, only: nml_group_type
  use demstep_cli, only: group_spec, cli_context
  use demstep_words, only: word_list
  use demstep_cli_system, only: handle_system, system_specs, system_doc
  use demstep_cli_harmonic, only: handle_harmonic_error, harmonic_specs, harmonic_doc
  use demstep_cli_stiffness, only: handle_simulated_stiffness, stiffness_specs, stiffness_doc
  use demstep_cli_scene, only: handle_scene, scene_specs, scene_doc, beside, scene_output_file
  use demstep_cli_files, only: input_file_type
  use demstep_cli_accuracy, only: handle_contact_error, contact_error_specs, contact_error_doc, &
    handle_accuracy_cost, accuracy_cost_specs, accuracy_cost_doc
  use demstep_cli_material, only: handle_material, material_specs, material_doc
  implicit none
  private

  public :: cli_groups, find_group, group_list, deck_inputs

contains

  !> Every group, in the order of the template.
  function cli_groups() result(groups)
    type(group_spec), allocatable :: groups(:)
    groups = [ &
      group_spec("system", system_doc, system_specs(), handle_system), &
      group_spec("harmonic_error", harmonic_doc, harmonic_specs(), handle_harmonic_error), &
      group_spec("simulated_stiffness", stiffness_doc, stiffness_specs(), handle_simulated_stiffness), &
      group_spec("scene", scene_doc, scene_specs(), run_scene), &
      group_spec("contact_error", contact_error_doc, contact_error_specs(), handle_contact_error), &
      group_spec("accuracy_cost", accuracy_cost_doc, accuracy_cost_specs(), handle_accuracy_cost), &
      group_spec("material", material_doc, material_specs(), handle_material) ]
  end function cli_groups

  !> The index of the group called `name` in `groups`, 0 when demstep does not know it.
  pure integer function find_group(groups, name) result(k)
    type(group_spec), intent(in) :: groups(:)
    character(len=*), intent(in) :: name
    do k = 1, size(groups)
      if (groups(k)%name == name) return
    end do
    k = 0
  end function find_group

  !> The group names as `&a, &b, ...`.
  pure function group_list(groups) result(text)
    type(group_spec), intent(in) :: groups(:)
    character(len=:), allocatable :: text
    character(len=64) :: names(size(groups))
    integer :: k
    do k = 1, size(groups)
      names(k) = "&"//groups(k)%name
    end do
    text = word_list(names)
  end function group_list

  !> The files a deck reads, which no output may replace: the deck, then every
  !> file a `&scene` names (its variables `*_file` but the one it writes, beside the deck as the handler
  !> opens them). A value the runtime cannot read as a file name is left out (the
  !> handler refuses it).
  function deck_inputs(deck, groups) result(inputs)
    !> The input deck's name.
    character(len=*), intent(in) :: deck
    !> The deck's groups (none for an MFiX deck).
    type(nml_group_type), intent(in) :: groups(:)
    type(input_file_type), allocatable :: inputs(:)
    ! as long as the handler's file name variables
    character(len=512) :: file
    character(len=:), allocatable :: text
    namelist /named/ file
    integer :: g, i, n, ios, m
    ! at most one file per &scene item: allocated once, filled, then cut
    m = 1
    do g = 1, size(groups)
      if (groups(g)%name == "scene") m = m + size(groups(g)%items)
    end do
    allocate(inputs(m))
    inputs(1) = input_file_type(deck, "the input deck")
    m = 1
    do g = 1, size(groups)
      if (groups(g)%name /= "scene") cycle
      do i = 1, size(groups(g)%items)
        associate(item => groups(g)%items(i))
          n = len(item%name)
          if (n < 5 .or. len(item%value) == 0) cycle
          if (item%name(max(1, n - 4):) /= "_file") cycle
          ! (a file the group writes is no input)
          if (item%name == scene_output_file) cycle
          file = ""
          text = "&named file = "//item%value//" /"
          read(text, nml=named, iostat=ios)
          if (ios /= 0 .or. len_trim(file) == 0) cycle
          m = m + 1
          inputs(m) = input_file_type(beside(deck, trim(file)), "the deck's &scene "//item%name)
        end associate
      end do
    end do
    inputs = inputs(:m)
  end function deck_inputs

  !> `&scene` reads its table files beside the deck.
  subroutine run_scene(ctx, group, status)
    type(cli_context), intent(in) :: ctx
    type(nml_group_type), intent(in) :: group
    type(demstep_status_type), intent(out) :: status
    call handle_scene(ctx, group, ctx%deck, status)
  end subroutine run_scene

end module demstep_cli_registry
